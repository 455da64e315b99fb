// Tests of the picture and ParaView writers on a synthetic spiral wire: the
// files must exist, be well-formed enough for their readers, and show the wire.

#include <wirefem/core/wire_state.h>
#include <wirefem/io/picture.h>
#include <wirefem/io/series_writer.h>
#include <wirefem/io/vtu_writer.h>

#include <cairo.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

namespace
{
  namespace fs = std::filesystem;
  using wirefem::core::Vec2;
  using wirefem::core::WireState;

  constexpr double pi = 3.14159265358979323846;

  /// A wire entering at (-r,0) and spiralling inwards for three turns, with
  /// bending energy from its discrete curvature and contact forces on part of
  /// the outer turn (where it would touch the wall).
  WireState spiral_wire(const double r = 20.0, const int n = 400)
  {
    WireState wire;
    wire.cavity_radius = r;
    wire.time = 1.0 / 3.0;
    for (int i = 0; i < n; ++i)
      {
        const double t = double(i) / (n - 1);
        const double angle = pi + 6.0 * pi * t;
        const double radius = r * (1.0 - 0.8 * t);
        wire.points.push_back({radius * std::cos(angle), radius * std::sin(angle)});
      }

    double s = 0.0;
    for (int i = 0; i < n; ++i)
      {
        if (i > 0)
          s += wirefem::core::norm(wire.points[i] - wire.points[i - 1]);
        wire.arc_length.push_back(s);
        double kappa = 0.0;
        if (i > 0 && i + 1 < n)
          {
            const Vec2 a = wire.points[i] - wire.points[i - 1];
            const Vec2 b = wire.points[i + 1] - wire.points[i];
            const double turn = std::atan2(wirefem::core::cross(a, b), wirefem::core::dot(a, b));
            kappa = 2.0 * turn / (wirefem::core::norm(a) + wirefem::core::norm(b));
          }
        wire.curvature.push_back(kappa);
        wire.plastic_curvature.push_back(0.5 * kappa);
        wire.bending_energy.push_back(0.5 * kappa * kappa);
        wire.contact_force.push_back(i > n / 10 && i < n / 5 ? 1.0 + 0.1 * i : 0.0);
      }
    wire.injected_length = s;
    return wire;
  }

  std::string read_all(const fs::path &file)
  {
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }

  std::uint32_t big_endian_u32(const std::string &bytes, const std::size_t at)
  {
    std::uint32_t v = 0;
    for (std::size_t i = 0; i < 4; ++i)
      v = (v << 8) | static_cast<unsigned char>(bytes[at + i]);
    return v;
  }

  /// Grey value in [0,1] of the pixel (i,j) of an opaque ARGB32 image.
  double grey_at(cairo_surface_t *image, const int i, const int j)
  {
    const unsigned char *data = cairo_image_surface_get_data(image);
    const int stride = cairo_image_surface_get_stride(image);
    std::uint32_t argb;
    std::copy_n(data + j * stride + 4 * i, 4, reinterpret_cast<unsigned char *>(&argb));
    const double red = (argb >> 16) & 0xff, green = (argb >> 8) & 0xff, blue = argb & 0xff;
    return (0.299 * red + 0.587 * green + 0.114 * blue) / 255.0;
  }

  class IoTest : public ::testing::Test
  {
  protected:
    void SetUp() override
    {
      std::random_device random;
      dir = fs::temp_directory_path() /
            ("wirefem_io_test_" + std::to_string(random()) + "_" + std::to_string(random()));
      fs::create_directories(dir);
    }
    void TearDown() override
    {
      std::error_code ignored;
      fs::remove_all(dir, ignored);
    }
    fs::path dir;
  };

  TEST_F(IoTest, PngHasSignatureSizeAndShowsTheWire)
  {
    const WireState wire = spiral_wire();
    const int size = 320;
    wirefem::io::PictureOptions options;
    options.size_px = size;
    options.caption = "spiral, t = 1/3";
    const fs::path png = dir / "wire.png", svg = dir / "wire.svg";
    wirefem::io::write_pictures(wire, png.string(), svg.string(), options);

    const std::string bytes = read_all(png);
    ASSERT_GE(bytes.size(), 24u);
    EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    EXPECT_EQ(bytes.substr(12, 4), "IHDR");
    EXPECT_EQ(big_endian_u32(bytes, 16), std::uint32_t(size));
    EXPECT_EQ(big_endian_u32(bytes, 20), std::uint32_t(size));

    cairo_surface_t *image = cairo_image_surface_create_from_png(png.c_str());
    ASSERT_EQ(cairo_surface_status(image), CAIRO_STATUS_SUCCESS);
    ASSERT_EQ(cairo_image_surface_get_width(image), size);

    int dark = 0;
    for (int j = 0; j < size; ++j)
      for (int i = 0; i < size; ++i)
        dark += grey_at(image, i, j) < 0.5;
    EXPECT_GT(dark, 100);
    EXPECT_LT(dark, size * size / 2);
    EXPECT_GT(grey_at(image, 0, 0), 0.99) << "the corner is background";

    // The segment with the largest bending energy is drawn black.
    std::size_t k_max = 0;
    for (std::size_t k = 0; k + 1 < wire.points.size(); ++k)
      if (wire.bending_energy[k] + wire.bending_energy[k + 1] >
          wire.bending_energy[k_max] + wire.bending_energy[k_max + 1])
        k_max = k;
    const Vec2 mid = 0.5 * (wire.points[k_max] + wire.points[k_max + 1]);
    const double scale = size / (2.1 * wire.cavity_radius);
    const int i = int((mid.x + 1.05 * wire.cavity_radius) * scale);
    const int j = int((1.05 * wire.cavity_radius - mid.y) * scale);
    EXPECT_LT(grey_at(image, i, j), 0.3);
    cairo_surface_destroy(image);

    const std::string svg_text = read_all(svg);
    ASSERT_FALSE(svg_text.empty());
    EXPECT_EQ(svg_text.front(), '<');
    EXPECT_NE(svg_text.find("<svg"), std::string::npos);
  }

  TEST_F(IoTest, PicturesToleratesMissingAndZeroFields)
  {
    WireState wire = spiral_wire();
    wire.contact_force.clear();
    std::fill(wire.bending_energy.begin(), wire.bending_energy.end(), 0.0);
    const fs::path png = dir / "a.png", svg = dir / "a.svg";
    EXPECT_NO_THROW(wirefem::io::write_pictures(wire, png.string(), svg.string()));
    EXPECT_TRUE(fs::exists(png));
    EXPECT_TRUE(fs::exists(svg));

    wire.contact_force.assign(wire.points.size(), 0.0);
    wire.bending_energy.clear();
    EXPECT_NO_THROW(wirefem::io::write_pictures(wire, png.string(), svg.string()));

    WireState empty;
    empty.cavity_radius = 5.0;
    EXPECT_NO_THROW(wirefem::io::write_pictures(empty, png.string(), svg.string()));
    EXPECT_TRUE(fs::exists(png));
  }

  TEST_F(IoTest, PicturesThrowForMissingDirectory)
  {
    const WireState wire = spiral_wire();
    const fs::path missing = dir / "no" / "such" / "dir";
    EXPECT_THROW(wirefem::io::write_pictures(wire, (missing / "a.png").string(), (dir / "a.svg").string()),
                 std::runtime_error);
    EXPECT_THROW(wirefem::io::write_pictures(wire, (dir / "a.png").string(), (missing / "a.svg").string()),
                 std::runtime_error);
    try
      {
        wirefem::io::write_pictures(wire, (missing / "named.png").string(), (dir / "a.svg").string());
      }
    catch (const std::runtime_error &e)
      {
        EXPECT_NE(std::string(e.what()).find("named.png"), std::string::npos) << e.what();
      }
  }

  TEST_F(IoTest, VtuContainsPointsCellsAndArrays)
  {
    WireState wire = spiral_wire(10.0, 57);
    wire.plastic_curvature.resize(3); // inconsistent: must be left out
    const fs::path vtu = dir / "wire.vtu";
    wirefem::io::write_vtu(vtu.string(), wire);

    const std::string text = read_all(vtu);
    EXPECT_NE(text.find("<VTKFile type=\"UnstructuredGrid\""), std::string::npos);
    EXPECT_NE(text.find("NumberOfPoints=\"57\""), std::string::npos);
    EXPECT_NE(text.find("NumberOfCells=\"56\""), std::string::npos);
    for (const char *name : {"arc_length", "curvature", "bending_energy", "contact_force"})
      EXPECT_NE(text.find("Name=\"" + std::string(name) + "\""), std::string::npos) << name;
    EXPECT_EQ(text.find("plastic_curvature"), std::string::npos);
    // Full precision: 1/3 printed with enough digits to round-trip.
    EXPECT_NE(text.find("0.33333333333333331"), std::string::npos);
    EXPECT_NE(text.find("</VTKFile>"), std::string::npos);

    // 56 cells of type 3 after the "types" header.
    const std::size_t types = text.find("Name=\"types\"");
    ASSERT_NE(types, std::string::npos);
    std::istringstream in(text.substr(text.find('>', types) + 1));
    int count = 0, type = 0;
    while (in >> type)
      {
        EXPECT_EQ(type, 3);
        ++count;
      }
    EXPECT_EQ(count, 56);

    EXPECT_THROW(wirefem::io::write_vtu((dir / "missing" / "w.vtu").string(), wire), std::runtime_error);
  }

  TEST_F(IoTest, PvdListsEntriesInOrderAndLeavesNoTemporary)
  {
    const fs::path pvd = dir / "run.pvd";
    wirefem::io::PvdCollection collection(pvd.string());
    collection.add(0.0, "wire_0000.vtu");
    collection.add(0.5, "wire_0001.vtu");
    wirefem::io::write_vtu((dir / "wire_0000.vtu").string(), spiral_wire());
    collection.write();
    collection.add(1.25, "sub dir/wire_0002.vtu");
    collection.write();
    ASSERT_EQ(collection.entries().size(), 3u);

    const std::string text = read_all(pvd);
    EXPECT_NE(text.find("type=\"Collection\""), std::string::npos);
    const std::string rest = "\" group=\"\" part=\"0\" file=\"";
    const std::size_t a = text.find("timestep=\"0" + rest + "wire_0000.vtu\"");
    const std::size_t b = text.find("timestep=\"0.5" + rest + "wire_0001.vtu\"");
    const std::size_t c = text.find("timestep=\"1.25" + rest + "sub dir/wire_0002.vtu\"");
    ASSERT_NE(a, std::string::npos);
    ASSERT_NE(b, std::string::npos);
    ASSERT_NE(c, std::string::npos);
    EXPECT_LT(a, b);
    EXPECT_LT(b, c);
    EXPECT_FALSE(fs::exists(pvd.string() + ".tmp"));

    wirefem::io::PvdCollection broken((dir / "missing" / "run.pvd").string());
    broken.add(0.0, "x.vtu");
    EXPECT_THROW(broken.write(), std::runtime_error);
    EXPECT_FALSE(fs::exists(dir / "missing"));
  }

  TEST(SeriesWriter, ResumeKeepsTheRowWrittenAtTheCheckpointStep)
  {
    // 1.23456789996 prints to 10 digits as 1.23456790, a little later than
    // itself: a checkpoint taken at that step must still keep that row.
    const std::string file = ::testing::TempDir() + "series_resume.csv";
    const double t = 1.23456789996;
    {
      wirefem::io::SeriesWriter w(file, {"time", "x"});
      w.write_row({1.0, 1.0});
      w.write_row({t, 2.0});
      w.write_row({2.0, 3.0}); // after the checkpoint: dropped on resume
    }
    {
      wirefem::io::SeriesWriter w(file, {"time", "x"}, t, 2);
      w.write_row({2.0, 4.0});
    }
    std::ifstream in(file);
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);)
      lines.push_back(l);
    ASSERT_EQ(lines.size(), 4u);
    EXPECT_EQ(lines[2].substr(0, lines[2].find(',')), "1.2345679");
    EXPECT_EQ(lines[3], "2,4");
  }

  TEST(SeriesWriter, ResumeRefusesAFileWithOtherColumnsAndLeavesIt)
  {
    // A run started by a version that wrote other columns: its rows must
    // not end up under this version's header, nor be lost.
    const std::string file = ::testing::TempDir() + "series_resume_columns.csv";
    {
      wirefem::io::SeriesWriter w(file, {"time", "x"});
      w.write_row({1.0, 1.0});
    }
    EXPECT_THROW(wirefem::io::SeriesWriter(file, {"time", "x", "y"}, 1.0, 1), wirefem::io::SeriesResumeError);
    std::ifstream in(file);
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);)
      lines.push_back(l);
    ASSERT_EQ(lines.size(), 2u);
    EXPECT_EQ(lines[0], "time,x");
    EXPECT_EQ(lines[1], "1,1");
  }

  TEST(SeriesWriter, ResumeRefusesAFileThatIsNotTheCheckpointsAndLeavesIt)
  {
    // The checkpoint counted three rows up to t = 3: a file with fewer (a
    // run started over in the directory), a damaged row among them, or no
    // file at all is refused, and the file stays byte for byte as it was.
    const std::string file = ::testing::TempDir() + "series_resume_rows.csv";
    auto write = [&](const std::string &text) { std::ofstream(file) << text; };
    auto read = [&] {
      std::ifstream in(file);
      return std::string(std::istreambuf_iterator<char>(in), {});
    };
    const std::vector<std::string> cases = {"time,x\n1,1\n2,2\n",         // a row short
                                            "time,x\n1,1\n2,2\n4,4\n",    // another run's rows
                                            "time,x\n1,1\n2,\xff\n3,3\n", // damaged
                                            "time,x\n1,1\nnan,2\n3,3\n",  // a time not finite
                                            "time,x\n1,1\n2\n3,3\n"};     // a value missing
    for (const auto &text : cases)
      {
        write(text);
        EXPECT_THROW(wirefem::io::SeriesWriter(file, {"time", "x"}, 3.0, 3), wirefem::io::SeriesResumeError)
            << text;
        EXPECT_EQ(read(), text);
      }
    std::filesystem::remove(file);
    EXPECT_THROW(wirefem::io::SeriesWriter(file, {"time", "x"}, 3.0, 3), wirefem::io::SeriesResumeError);
    EXPECT_FALSE(std::filesystem::exists(file));
    // The checkpoint's rows (inf and nan are values the writer prints), and
    // a damaged row after them: cut with the rest.
    write("time,x\n1,1\n2,inf\n3,nan\n4,\n");
    {
      wirefem::io::SeriesWriter w(file, {"time", "x"}, 3.0, 3);
      w.write_row({4.0, 4.0});
    }
    EXPECT_EQ(read(), "time,x\n1,1\n2,inf\n3,nan\n4,4\n");
    EXPECT_FALSE(std::filesystem::exists(file + ".tmp"));
  }
} // namespace
