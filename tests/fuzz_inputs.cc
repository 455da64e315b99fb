// Fuzzing the readers (ctest -L stress): mutated scene files and --set
// overrides, mutated CSV shapes, and randomly damaged checkpoints. Each
// input must be read, or refused with core::InputError in one line; any
// other exception, or a crash, fails. A damaged checkpoint must be refused
// and leave every file of its run directory as it was.
//   wirefem_fuzz SOURCE_DIR WORK_DIR [SCENES [SHAPES [CHECKPOINTS]]]
#include <wirefem/analysis/observables.h>
#include <wirefem/analysis/shape_io.h>
#include <wirefem/core/input_error.h>
#include <wirefem/scene/scene_reader.h>
#include <wirefem/simulation/simulation.h>

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace
{
  namespace fs = std::filesystem;
  using namespace wirefem;

  std::string read_file(const fs::path &file)
  {
    std::ifstream in(file, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }

  void write_file(const fs::path &file, const std::string &bytes)
  {
    std::ofstream(file, std::ios::binary) << bytes;
  }

  /// Text pieces a hand-edited or damaged file might hold.
  const std::vector<std::string> tokens = {"set ",
                                           "subsection ",
                                           "end\n",
                                           " = ",
                                           "=",
                                           "#",
                                           "\\\n",
                                           "\n",
                                           "nan",
                                           "inf",
                                           "-inf",
                                           "-1",
                                           "0",
                                           "-0",
                                           "1e400",
                                           "-1e308",
                                           "1e-320",
                                           "0x1p3",
                                           "3.",
                                           ".5",
                                           "1e",
                                           "true",
                                           "false",
                                           "fem",
                                           "discrete",
                                           "reissner",
                                           "Cavity/Radius=",
                                           "Model=",
                                           "Injection/Speed=",
                                           "FEM/Degree=",
                                           "Contact/Normal stiffness=",
                                           std::string(300, '9'),
                                           std::string("\0", 1),
                                           "\x1b[31m",
                                           "\xff\xfe",
                                           "\xc3\xa9",
                                           "subsection Cavity\n",
                                           "set Radius = 1e9\n"};

  /// One to four random edits of `text`: bits flipped, bytes overwritten,
  /// tokens or random bytes inserted, ranges deleted, lines repeated or
  /// swapped, the end cut.
  std::string mutate(std::string text, std::mt19937_64 &rng)
  {
    auto pick = [&](const std::size_t n) {
      return n ? std::uniform_int_distribution<std::size_t>(0, n - 1)(rng) : 0;
    };
    const std::size_t edits = 1 + pick(4);
    for (std::size_t e = 0; e < edits; ++e)
      {
        const std::size_t at = pick(text.size() + 1);
        switch (pick(8))
          {
          case 0:
            if (!text.empty())
              text[pick(text.size())] ^= static_cast<char>(1u << pick(8));
            break;
          case 1:
            if (!text.empty())
              text[pick(text.size())] = static_cast<char>(pick(256));
            break;
          case 2:
            text.insert(at, tokens[pick(tokens.size())]);
            break;
          case 3:
            {
              std::string junk(1 + pick(16), ' ');
              for (auto &c : junk)
                c = static_cast<char>(pick(256));
              text.insert(at, junk);
              break;
            }
          case 4:
            text.erase(at, pick(64));
            break;
          case 5:
          case 6:
            {
              // A whole line repeated elsewhere (a key set twice), or two swapped.
              std::vector<std::string> lines;
              std::istringstream in(text);
              for (std::string l; std::getline(in, l);)
                lines.push_back(l);
              if (lines.size() < 2)
                break;
              const std::size_t a = pick(lines.size()), b = pick(lines.size());
              if (e % 2)
                std::swap(lines[a], lines[b]);
              else
                lines.insert(lines.begin() + b, lines[a]);
              text.clear();
              for (const auto &l : lines)
                text += l + "\n";
              break;
            }
          default:
            text.resize(at);
          }
      }
    return text;
  }

  struct Tally
  {
    long read = 0, refused = 0;
    std::vector<std::string> failures;
  };

  /// Runs `body`: fine if it returns, or throws InputError whose message
  /// names the input (starts with `input`) and is one line with no control
  /// character; anything else is a failure described with `what`.
  template <typename Body>
  void expect_read_or_refused(Tally &tally, const std::string &what, const std::string &input, Body &&body)
  {
    try
      {
        body();
        ++tally.read;
      }
    catch (const core::InputError &e)
      {
        ++tally.refused;
        const std::string msg = e.what();
        if (msg.rfind(input, 0) != 0)
          tally.failures.push_back(what + ": the message does not start with " + input + ": " + msg);
        if (std::any_of(msg.begin(), msg.end(), [](const char c) { return c >= 0 && c < 0x20; }))
          tally.failures.push_back(what + ": the message holds a control character: " + msg);
      }
    catch (const std::exception &e)
      {
        tally.failures.push_back(what + ": " + e.what());
      }
  }

  Tally fuzz_scenes(const fs::path &source, const fs::path &work, const long n, std::mt19937_64 &rng)
  {
    std::vector<std::string> bases;
    for (const auto &entry : fs::directory_iterator(source / "prm"))
      if (entry.path().extension() == ".prm")
        bases.push_back(read_file(entry.path()));
    Tally tally;
    const fs::path file = work / "fuzz.prm";
    for (long k = 0; k < n; ++k)
      {
        const std::string text = mutate(bases[k % bases.size()], rng);
        write_file(file, text);
        std::vector<std::string> overrides;
        if (k % 4 == 0)
          overrides.push_back(mutate("Cavity/Radius=25", rng));
        expect_read_or_refused(tally, "scene " + std::to_string(k), file.string(), [&] {
          const auto scene = scene::read_scene(file.string(), overrides);
          (void)scene;
        });
        if (tally.failures.size() == 1 && !fs::exists(work / "first_failing.prm"))
          write_file(work / "first_failing.prm", text);
      }
    return tally;
  }

  Tally fuzz_shapes(const fs::path &work, const long n, std::mt19937_64 &rng)
  {
    // A wire with a teardrop loop, as x,y rows with a header and metadata.
    std::ostringstream base;
    base << "# diameter = 1\n# radius = 10\nx,y\n";
    for (int k = 0; k <= 120; ++k)
      {
        const double t = 2.0 * M_PI * k / 120.0;
        base << 6.0 * std::sin(t) << "," << 3.0 * (1.0 - std::cos(t)) * std::sin(0.5 * t) << "\n";
      }
    Tally tally;
    const fs::path file = work / "fuzz.csv";
    for (long k = 0; k < n; ++k)
      {
        write_file(file, mutate(base.str(), rng));
        expect_read_or_refused(tally, "shape " + std::to_string(k), file.string(), [&] {
          const auto wire = analysis::read_shape(file.string(), {});
          (void)analysis::analysis_report(wire, wire.cavity_radius > 0.0);
        });
      }
    return tally;
  }

  std::map<std::string, std::string> snapshot(const fs::path &dir)
  {
    std::map<std::string, std::string> files;
    for (const auto &entry : fs::directory_iterator(dir))
      files[entry.path().filename().string()] = read_file(entry.path());
    return files;
  }

  Tally fuzz_checkpoints(const fs::path &source, const fs::path &work, const long n, std::mt19937_64 &rng)
  {
    // A small run interrupted (SIGINT, as a user would) once it is stepping.
    const fs::path dir = work / "run";
    fs::remove_all(dir);
    const auto scene = scene::read_scene((source / "prm" / "quick.prm").string(),
                                         {"Cavity/Radius=20", "Output/Directory=" + dir.string(),
                                          "Output/Progress=off", "Output/VTU interval=0"});
    // The run installs its own handler while it steps; outside it a late
    // signal is ignored (and the run reported as not interrupted).
    std::signal(SIGINT, SIG_IGN);
    std::thread interrupt([&] {
      for (int i = 0; i < 3000 && !fs::exists(dir / "series.csv"); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      std::raise(SIGINT);
    });
    std::ostringstream quiet;
    auto *old = std::cout.rdbuf(quiet.rdbuf());
    const auto first = simulation::run(scene, {});
    interrupt.join();
    Tally tally;
    if (!first.interrupted || !fs::exists(dir / "checkpoint.bin"))
      {
        std::cout.rdbuf(old);
        tally.failures.push_back("the run to damage ended before it was interrupted");
        return tally;
      }
    const std::string good = read_file(dir / "checkpoint.bin");
    for (long k = 0; k < n; ++k)
      {
        std::string bad = good;
        auto pick = [&](const std::size_t m) {
          return std::uniform_int_distribution<std::size_t>(0, m - 1)(rng);
        };
        switch (k % 5)
          {
          case 0:
            bad[pick(bad.size())] ^= static_cast<char>(1u << pick(8));
            break;
          case 1:
            for (std::size_t i = pick(bad.size()), e = std::min(bad.size(), i + 1 + pick(64)); i < e; ++i)
              bad[i] = static_cast<char>(pick(256));
            break;
          case 2:
            bad.resize(pick(bad.size()));
            break;
          case 3:
            bad += std::string(1 + pick(32), '\0');
            break;
          default:
            bad[pick(32)] ^= static_cast<char>(1u << pick(8)); // the header: magic, version, size, checksum
          }
        if (bad == good)
          continue;
        write_file(dir / "checkpoint.bin", bad);
        const auto before = snapshot(dir);
        expect_read_or_refused(tally, "checkpoint " + std::to_string(k), dir.string(), [&] {
          (void)simulation::run(scene, {true});
          tally.failures.push_back("checkpoint " + std::to_string(k) + ": a damaged checkpoint was resumed");
        });
        if (snapshot(dir) != before)
          tally.failures.push_back("checkpoint " + std::to_string(k) + ": the run directory changed");
      }
    std::cout.rdbuf(old);
    return tally;
  }
} // namespace

int main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  if (argc < 3)
    {
      std::cerr << "usage: wirefem_fuzz SOURCE_DIR WORK_DIR [SCENES [SHAPES [CHECKPOINTS]]]\n";
      return 2;
    }
  const fs::path source = argv[1], work = argv[2];
  const long scenes = argc > 3 ? std::stol(argv[3]) : 10000;
  const long shapes = argc > 4 ? std::stol(argv[4]) : 3000;
  const long checkpoints = argc > 5 ? std::stol(argv[5]) : 300;
  fs::create_directories(work);
  std::mt19937_64 rng(20261205);
  const std::vector<std::pair<std::string, Tally>> results = {
      {"scene files", fuzz_scenes(source, work, scenes, rng)},
      {"CSV shapes", fuzz_shapes(work, shapes, rng)},
      {"checkpoints", fuzz_checkpoints(source, work, checkpoints, rng)}};
  bool ok = true;
  for (const auto &[name, t] : results)
    {
      std::cout << name << ": " << t.read << " read, " << t.refused << " refused in one line, "
                << t.failures.size() << " failures\n";
      for (std::size_t i = 0; i < std::min<std::size_t>(t.failures.size(), 5); ++i)
        std::cout << "  " << t.failures[i] << "\n";
      ok = ok && t.failures.empty();
    }
  std::cout << (ok ? "PASS" : "FAIL") << std::endl;
  return ok ? 0 : 1;
}
