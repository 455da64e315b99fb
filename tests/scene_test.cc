// Scene reading: defaults, overrides, and one-line errors naming file, key and reason.
#include <wirefem/scene/cavity_setup.h>
#include <wirefem/scene/scene_reader.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace
{
  using wirefem::scene::InputError;
  using wirefem::scene::read_scene;

  std::string error_of(const std::string &file, const std::vector<std::string> &overrides)
  {
    try
      {
        read_scene(file, overrides);
      }
    catch (const InputError &e)
      {
        return e.what();
      }
    return "";
  }

  std::string write_prm(const std::string &name, const std::string &text)
  {
    const auto path = std::filesystem::temp_directory_path() / name;
    std::ofstream(path) << text;
    return path.string();
  }

  TEST(Scene, ReadsFileAndAppliesOverridesInOrder)
  {
    const auto f = write_prm("wirefem_scene_ok.prm", "subsection Cavity\n  set Radius = 12 # comment\nend\n"
                                                     "subsection Contact\n subsection Friction\n"
                                                     "  set Static coefficient = 0.3\n end\nend\n");
    const auto s = read_scene(f, {"contact/friction/static coefficient = 0.4", "Injection/Seed=7"});
    EXPECT_DOUBLE_EQ(s.cavity.radius, 12.0);
    EXPECT_DOUBLE_EQ(s.contact.friction.static_coefficient, 0.4);
    EXPECT_DOUBLE_EQ(s.contact.friction.dynamic_coefficient, 0.8 * 0.4);
    EXPECT_DOUBLE_EQ(s.contact.friction.wall_static_coefficient, 0.4);
    EXPECT_EQ(s.injection.seed, 7u);
    EXPECT_EQ(s.name, "wirefem_scene_ok");
    EXPECT_EQ(s.output.directory, "output/wirefem_scene_ok");
  }

  TEST(Scene, FingerprintHoldsEveryKeyButWhereOutputGoes)
  {
    const auto base = read_scene("", {});
    // One line per key of --print-parameters outside the Output subsection.
    std::ostringstream printed;
    wirefem::scene::print_parameters(printed);
    std::istringstream in(printed.str());
    int keys = 0, depth = 0, output_depth = -1;
    for (std::string line; std::getline(in, line);)
      {
        const auto first = line.find_first_not_of(' ');
        if (first == std::string::npos)
          continue;
        const std::string word = line.substr(first, line.find(' ', first) - first);
        if (word == "subsection")
          {
            if (line.find("Output") != std::string::npos && output_depth < 0)
              output_depth = depth;
            ++depth;
          }
        else if (word == "end")
          {
            --depth;
            if (depth == output_depth)
              output_depth = -1;
          }
        else if (word == "set" && output_depth < 0)
          ++keys;
      }
    EXPECT_GT(keys, 60);
    // ... and the two Output keys that set what the files hold.
    EXPECT_EQ(std::count(base.fingerprint.begin(), base.fingerprint.end(), '\n'), keys + 2)
        << base.fingerprint;
    EXPECT_NE(read_scene("", {"Output/Interval=2"}).fingerprint, base.fingerprint);
    EXPECT_NE(read_scene("", {"Output/VTU interval=2"}).fingerprint, base.fingerprint);
    // The key the hand-kept list had missed, and any other, changes it;
    // output settings and the spelling of a number do not.
    EXPECT_NE(read_scene("", {"Injection/Channels=tangential"}).fingerprint, base.fingerprint);
    EXPECT_NE(read_scene("", {"FEM/Maximum iterations=20"}).fingerprint, base.fingerprint);
    EXPECT_EQ(read_scene("", {"Output/Directory=elsewhere", "Output/Progress=off"}).fingerprint,
              base.fingerprint);
    EXPECT_EQ(read_scene("", {"Cavity/Radius=25"}).fingerprint,
              read_scene("", {"Cavity/Radius=25.000"}).fingerprint);
    EXPECT_NE(base.fingerprint.find("Injection/Channels = radial\n"), std::string::npos) << base.fingerprint;
  }

  TEST(Scene, BadInputNamesFileKeyAndReason)
  {
    const auto f = write_prm("wirefem_scene_bad.prm", "set Model = discrete\n");
    struct Case
    {
      std::vector<std::string> overrides;
      std::string key, reason;
    };
    for (const auto &c : std::vector<Case>{
             {{"Cavity/Radius=-3"}, "Cavity/Radius", "larger than 1"},
             {{"Cavity/Radius=twelve"}, "Cavity/Radius", "'twelve' is not a valid value"},
             {{"Cavity/No such key=1"}, "Cavity/No such key", "no such key"},
             {{"Contact/Friction/Static coefficient=0.2", "Contact/Friction/Dynamic coefficient=0.3"},
              "Contact/Friction/Dynamic coefficient",
              "exceeds the static coefficient"},
             {{"Injection/Maximum packing density=0.01"},
              "Injection/Maximum packing density",
              "must exceed the initial packing density"},
             {{"Wire/Plasticity/Hardening slope=1.5"}, "Wire/Plasticity/Hardening slope", "[0, 1]"},
             {{"Discrete/Segment length=0.3"}, "Discrete/Segment length", "whole number"},
             {{"Cavity/Radius"}, "Cavity/Radius", "expected"},
             {{"Injection/Slow start length=0.01", "Injection/Ramp time=10"},
              "Injection/Slow start length",
              "at least what the ramp injects"},
             {{"Injection/Slow start length=5", "Injection/Slow start speed=0"},
              "Injection/Slow start speed",
              "must be positive"},
             {{"Model=fem", "Contact/Friction/Surface torque=true"},
              "Contact/Friction/Surface torque",
              "Model = discrete only"},
             {{"Cavity/Shape=polygon", "Cavity/Vertices=0,0,4,4,4,0,1,5"}, "Cavity/Vertices", "cross"},
             {{"Cavity/Shape=polygon", "Cavity/Corner radius=30"}, "Cavity/Corner radius", "too large"},
             {{"Cavity/Shape=ellipse", "Cavity/Aspect ratio=0.5"}, "Cavity/Aspect ratio", "at least 1"},
             {{"Injection/Channel positions=0.5, 1.2"}, "Injection/Channel positions", "off the wall"},
             {{"Injection/Channel positions=0.5, 0.51"}, "Injection/Channel positions", "overlap"},
             {{"Injection/Channel positions=0.1, 0.4, 0.7"}, "Injection/Channel positions", "one or two"},
             {{"Injection/Channel angle=85"}, "Injection/Channel angle", "below 80"},
             {{"Cavity/Shape=polygon", "Cavity/Corner radius=0.5"}, "Cavity/Corner radius", "at least 1"},
             {{"Cavity/Shape=ellipse", "Cavity/Aspect ratio=20"}, "Cavity/Aspect ratio", "tighter than d"},
             {{"Cavity/Radius=25", "Injection/Channel positions=0, 0.02674", "Injection/Channel angle=75"},
              "Injection/Channel positions",
              "overlap"},
             {{"Injection/Channels=tangential", "Injection/Channel angle=30"},
              "Injection/Channels",
              "circle"},
             {{"Model=fem", "FEM/Newton=modified", "FEM/Linear solver=kept factors"},
              "FEM/Newton",
              "needs FEM/Linear solver = refactorise"},
             {{"Model=fem", "FEM/Linear solver=band", "FEM/Linear tolerance=1"},
              "FEM/Linear tolerance",
              "must be below 1"},
             {{"Model=fem", "FEM/Self friction law=spring", "FEM/Integrator=explicit"},
              "FEM/Self friction law",
              "needs an implicit integrator"},
             {{"Model=fem", "FEM/Self friction law=spring", "FEM/Contact points=2"},
              "FEM/Self friction law",
              "needs FEM/Contact points = 0"},
         })
      {
        const auto msg = error_of(f, c.overrides);
        EXPECT_NE(msg.find(f), std::string::npos) << msg;
        EXPECT_NE(msg.find(c.key), std::string::npos) << msg;
        EXPECT_NE(msg.find(c.reason), std::string::npos) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
      }
  }

  TEST(Scene, TheAutomaticSelfFrictionLawIsTheSpringsWithImplicitDynamicsAtTheNodes)
  {
    // FEM/Self friction law = auto: the discrete model's springs where they
    // are implemented and paid off (generalized-alpha, contact at the
    // nodes), the regularised law elsewhere; a named law is taken as it is.
    const auto springs = [](std::vector<std::string> o) {
      o.insert(o.begin(), "Model=fem");
      return read_scene("", o).fem.spring_self_friction;
    };
    EXPECT_TRUE(springs({}));
    EXPECT_FALSE(springs({"FEM/Integrator=quasi-static"}));
    EXPECT_FALSE(springs({"FEM/Integrator=explicit"}));
    EXPECT_FALSE(springs({"FEM/Contact points=2"}));
    EXPECT_FALSE(springs({"FEM/Self friction law=regularised"}));
    EXPECT_TRUE(springs({"FEM/Integrator=quasi-static", "FEM/Self friction law=spring"}));
  }

  TEST(Scene, TheLinearSolverIsAutoUnlessModifiedNewtonKeepsItsOwnFactors)
  {
    // FEM/Linear solver = auto, the default, is the band with
    // generalized-alpha; modified Newton reuses LU factors of its own, so
    // auto is then refactorise. A named solver is taken as it is, and
    // GMRES's defaults follow the solver.
    const auto fem = [](std::vector<std::string> o) {
      o.insert(o.begin(), "Model=fem");
      return read_scene("", o).fem;
    };
    using wirefem::scene::LinearSolver;
    EXPECT_EQ(fem({}).linear_solver, LinearSolver::automatic);
    EXPECT_EQ(fem({}).linear_tolerance, 1e-3);
    EXPECT_EQ(fem({}).krylov_iterations, 30u);
    EXPECT_EQ(fem({"FEM/Newton=modified"}).linear_solver, LinearSolver::refactorise);
    EXPECT_EQ(fem({"FEM/Linear solver=band"}).linear_solver, LinearSolver::band);
    EXPECT_EQ(fem({"FEM/Linear solver=kept factors"}).linear_tolerance, 1e-9);
    EXPECT_EQ(fem({"FEM/Linear solver=kept factors"}).krylov_iterations, 8u);
    EXPECT_EQ(fem({"FEM/Newton=modified", "FEM/Linear solver=refactorise"}).linear_solver,
              LinearSolver::refactorise);
  }

  TEST(Scene, PolygonVerticesComeFromAFileBesideTheScene)
  {
    const auto dir = std::filesystem::temp_directory_path() / "wirefem_vertex_file";
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "square.txt") << "# a square\n-1 -1\n1 -1\n\n1 1   # top right\n-1 1\n";
    std::ofstream(dir / "bad.txt") << "0 0\n4 x\n";
    const auto prm = (dir / "scene.prm").string();
    std::ofstream(prm) << "subsection Cavity\n  set Shape = polygon\n  set Vertex file = square.txt\nend\n";
    const auto s = read_scene(prm, {"Cavity/Vertices=0, 0, 5, 0, 0, 5"});
    EXPECT_EQ(s.cavity.vertices, (std::vector<double>{-1, -1, 1, -1, 1, 1, -1, 1}));
    EXPECT_NE(s.fingerprint.find("Vertex file numbers = -1, -1, 1, -1, 1, 1, -1, 1"), std::string::npos);
    const auto bad = error_of(prm, {"Cavity/Vertex file=bad.txt"});
    EXPECT_NE(bad.find("Cavity/Vertex file"), std::string::npos) << bad;
    EXPECT_NE(bad.find("bad.txt:2: '4 x' is not two numbers"), std::string::npos) << bad;
    const auto missing = error_of(prm, {"Cavity/Vertex file=none.txt"});
    EXPECT_NE(missing.find("Cavity/Vertex file: cannot open"), std::string::npos) << missing;
  }

  TEST(Scene, ChannelsAreCheckedAgainstTheWallTheyCut)
  {
    const auto f = write_prm("wirefem_scene_channels.prm", "set Model = discrete\n");
    // Steep channels on the circle are fine: the wire leaves them through
    // the mouth, clear of its corners.
    for (const auto angle : {"30", "60", "75"})
      EXPECT_EQ(error_of(f, {"Cavity/Radius=25", std::string("Injection/Channel angle=") + angle}), "")
          << angle;
    // A U-shaped cavity with a channel in the inner side of its left arm,
    // pointing into that arm: behind it the channel runs through the gap
    // and on into the right arm.
    wirefem::scene::CavityParameters c;
    c.radius = 25;
    c.shape = wirefem::scene::CavityShape::polygon;
    c.vertices = {0, 0, 30, 0, 30, 30, 20, 30, 20, 10, 10, 10, 10, 30, 0, 30};
    const auto wall = wirefem::scene::cavity_wall(c);
    // The left arm's inner side is the edge x = 10, y in (10, 30) of the
    // unscaled polygon: find its midpoint's place along the scaled wall.
    // The unscaled polygon: area 700, centroid (15, 13.571); the arcs cut
    // a little off, so the scale is about sqrt(pi 625 / 700).
    const double scale = std::sqrt(M_PI * 625.0 / 700.0);
    double best = 0.0, best_distance = 1e300;
    for (int k = 0; k < 20000; ++k)
      {
        const double s = wall.perimeter() * k / 20000.0;
        const auto q = wall.at(s).point;
        const double d = std::hypot(q.x - (10 - 15) * scale, q.y - (20 - 13.571) * scale);
        if (d < best_distance)
          best = s, best_distance = d;
      }
    const double start = wirefem::scene::wall_start(wall);
    const double fraction =
        std::fmod(best - start + 2 * wall.perimeter(), wall.perimeter()) / wall.perimeter();
    const auto msg =
        error_of(f, {"Cavity/Radius=25", "Cavity/Shape=polygon",
                     "Cavity/Vertices=0, 0, 30, 0, 30, 30, 20, 30, 20, 10, 10, 10, 10, 30, 0, 30",
                     "Injection/Channel positions=" + std::to_string(fraction) + ", 0.02"});
    EXPECT_NE(msg.find("Injection/Channel positions"), std::string::npos) << msg;
    EXPECT_NE(msg.find("runs back through the cavity"), std::string::npos) << msg;
  }

  TEST(Scene, FileErrorsCarryTheLineNumber)
  {
    const auto f =
        write_prm("wirefem_scene_line.prm", "subsection Cavity\n  set Radius = 10\n  set Radus = 3\nend\n");
    const auto msg = error_of(f, {});
    EXPECT_NE(msg.find(f + ":3"), std::string::npos) << msg;
    EXPECT_NE(msg.find("Cavity/Radus"), std::string::npos) << msg;
    const auto g = write_prm("wirefem_scene_open.prm", "subsection Cavity\n  set Radius = 10\n");
    EXPECT_NE(error_of(g, {}).find("not closed"), std::string::npos);
  }

  TEST(Scene, AKeySetTwiceInOneFileNamesBothLines)
  {
    // Spelled differently (case, a subsection closed and reopened), still
    // one key; an override on the command line is no repetition.
    const auto f =
        write_prm("wirefem_scene_twice.prm",
                  "subsection Cavity\n  set Radius = 12\nend\n\nsubsection cavity\n  set radius = 14\nend\n");
    const auto msg = error_of(f, {});
    EXPECT_NE(msg.find(f + ":6: cavity/radius: set again (first set on line 2)"), std::string::npos) << msg;
    const auto g = write_prm("wirefem_scene_once.prm", "subsection Cavity\n  set Radius = 12\nend\n");
    EXPECT_EQ(read_scene(g, {"Cavity/Radius=14"}).cavity.radius, 14.0);
  }

  TEST(Scene, TheCavityIsCheckedAgainstItsWireBeforeAnythingIsAllocated)
  {
    // Too narrow for 8 segments across, or a wire at the maximum packing
    // density that would not fit in memory: refused, the radius named.
    for (const std::string r : {"1.0001", "3.5"})
      EXPECT_NE(error_of("", {"Cavity/Radius=" + r}).find("Cavity/Radius: r = " + r + " is less than 4 x"),
                std::string::npos)
          << r;
    for (const std::string model : {"discrete", "fem"})
      EXPECT_NE(
          error_of("", {"Model=" + model, "Cavity/Radius=1e9"}).find("Cavity/Radius: r = 1e+09 needs about"),
          std::string::npos)
          << model;
    EXPECT_EQ(read_scene("", {"Cavity/Radius=4"}).cavity.radius, 4.0);
    // The element of the model that runs, not of the other one.
    EXPECT_NE(error_of("", {"Model=fem", "Cavity/Radius=25", "FEM/Element length=10"})
                  .find("Cavity/Radius: r = 25 is less than 4 x FEM/Element length (10)"),
              std::string::npos);
    EXPECT_EQ(read_scene("", {"Cavity/Radius=25", "FEM/Element length=10"}).fem.element_length, 10.0);
  }

  TEST(Scene, BadInputIsOneLineThatATerminalShowsAsIs)
  {
    // Newlines, escape sequences and bytes that are not UTF-8 from a
    // damaged file or a --set come out as \xNN; UTF-8 text stays.
    const std::string raw = std::string("a\nb\x1b[31m\xff\xc3\xa9\xc2\x9b") + '\0' + "z";
    EXPECT_EQ(InputError(raw).what(), std::string("a\\x0ab\\x1b[31m\\xff\xc3\xa9\\xc2\\x9b\\x00z"));
    // A number the pattern lets through but a double cannot hold.
    for (const std::string v : {"1e-32050"})
      EXPECT_NE(error_of("", {"Injection/Jamming force=" + v})
                    .find("Injection/Jamming force: '" + v + "' is out of the range of a double"),
                std::string::npos)
          << v;
    const auto msg = error_of("", {"Cavity/Radius=1\n2"});
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    EXPECT_NE(msg.find("Cavity/Radius: '1\\x0a2'"), std::string::npos) << msg;
  }

  TEST(Scene, MissingFileIsAnError)
  {
    const auto msg = error_of("/nonexistent/absent.prm", {});
    EXPECT_NE(msg.find("absent.prm"), std::string::npos) << msg;
  }

  TEST(Scene, PrintParametersListsEveryContractKey)
  {
    std::ostringstream out;
    wirefem::scene::print_parameters(out);
    for (const auto key : {"Model", "Radius", "Axial stiffness", "Bending stiffness", "Mass per length",
                           "Yield curvature", "Hardening slope", "Static coefficient", "Dynamic coefficient",
                           "Speed", "Seed", "Maximum packing density", "Directory"})
      EXPECT_NE(out.str().find(std::string("set ") + key), std::string::npos) << key;
  }
} // namespace
