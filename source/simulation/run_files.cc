#include <wirefem/core/binary.h>
#include <wirefem/scene/scene_reader.h>

#include "run_files.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace wirefem::simulation
{
  namespace
  {
    constexpr std::uint64_t checkpoint_magic = 0x77666d72756e3031ull; // "wfmrun01"
    /// Layout of checkpoint.bin: magic, version, payload size, FNV-1a 64
    /// checksum of the payload, payload (fingerprint, loop state, pvd
    /// entries, the model's state).
    constexpr std::uint64_t checkpoint_version = 7;

    std::uint64_t fnv1a(const std::string &bytes)
    {
      std::uint64_t h = 0xcbf29ce484222325ull;
      for (const unsigned char c : bytes)
        {
          h ^= c;
          h *= 0x100000001b3ull;
        }
      return h;
    }

    bool finite(const LoopState &l)
    {
      for (const double x :
           {l.next_row, l.next_vtu, l.force_mean, l.previous_length, l.max_penetration, l.wall_time})
        if (!std::isfinite(x))
          return false;
      return l.vtu_count >= 0;
    }

    bool finite(const core::EnergyLedger &e)
    {
      for (const double x : {e.stretching, e.shear, e.bending, e.contact, e.kinetic, e.plastic, e.friction,
                             e.friction_stored, e.damping, e.injection_work, e.initial})
        if (!std::isfinite(x))
          return false;
      return true;
    }

    // The first key whose value differs between two scene fingerprints
    // (scene::Scene::fingerprint), for the message that refuses a resume.
    std::string first_difference(const std::string &here, const std::string &there)
    {
      const auto lines = [](const std::string &text) {
        std::map<std::string, std::string> m;
        std::istringstream in(text);
        for (std::string line; std::getline(in, line);)
          if (const auto eq = line.find(" = "); eq != std::string::npos)
            m[line.substr(0, eq)] = line.substr(eq + 3);
        return m;
      };
      const auto a = lines(here), b = lines(there);
      for (const auto &[key, value] : a)
        if (const auto it = b.find(key); it == b.end() || it->second != value)
          return fmt::format("{} is {} here and {} in the checkpoint", key, value,
                             it == b.end() ? std::string("absent") : it->second);
      for (const auto &[key, value] : b)
        if (a.find(key) == a.end())
          return fmt::format("{} is in the checkpoint but not in this scene", key);
      return "different scene parameters";
    }

    /// A file that a run writes into its output directory (docs/output.md).
    bool is_run_file(const std::filesystem::path &p)
    {
      // A file being replaced atomically ends in .tmp until it is renamed.
      std::string name = p.filename().string();
      if (name.size() > 4 && name.compare(name.size() - 4, 4, ".tmp") == 0)
        name.resize(name.size() - 4);
      for (const char *own : {"checkpoint.bin", "summary.json", "series.csv", "wire.pvd", "final.png",
                              "final.svg", "fits.png", "fits.svg", "shape.csv", "history.csv", "profile.csv"})
        if (name == own)
          return true;
      return name.size() > 9 && name.rfind("wire_", 0) == 0 && name.compare(name.size() - 4, 4, ".vtu") == 0;
    }

    std::vector<std::filesystem::path> run_files(const std::filesystem::path &dir)
    {
      std::vector<std::filesystem::path> files;
      std::error_code ec;
      if (std::filesystem::is_directory(dir, ec))
        for (const auto &entry : std::filesystem::directory_iterator(dir, ec))
          if (is_run_file(entry.path()))
            files.push_back(entry.path());
      std::sort(files.begin(), files.end());
      return files;
    }
  } // namespace

  void write_checkpoint(const std::filesystem::path &file, const scene::Scene &scene, const LoopState &loop,
                        const io::PvdCollection &pvd, const core::Model &model)
  {
    // Written next to the final name and renamed, so an interruption while
    // writing leaves the previous checkpoint intact.
    const auto tmp = file.string() + ".tmp";
    {
      std::ostringstream out(std::ios::binary);
      const auto &fp = scene.fingerprint;
      core::write_raw(out, static_cast<std::uint64_t>(fp.size()));
      out.write(fp.data(), static_cast<std::streamsize>(fp.size()));
      core::write_raw(out, loop);
      core::write_raw(out, static_cast<std::uint64_t>(pvd.entries().size()));
      for (const auto &[time, name] : pvd.entries())
        {
          core::write_raw(out, time);
          core::write_raw(out, static_cast<std::uint64_t>(name.size()));
          out.write(name.data(), static_cast<std::streamsize>(name.size()));
        }
      model.save(out);
      const std::string payload = out.str();
      std::ofstream file_out(tmp, std::ios::binary);
      core::write_raw(file_out, checkpoint_magic);
      core::write_raw(file_out, checkpoint_version);
      core::write_raw(file_out, static_cast<std::uint64_t>(payload.size()));
      core::write_raw(file_out, fnv1a(payload));
      file_out.write(payload.data(), static_cast<std::streamsize>(payload.size()));
      if (!file_out)
        throw std::runtime_error("cannot write " + tmp);
    }
    std::filesystem::rename(tmp, file);
  }

  void read_checkpoint(const std::filesystem::path &file, const scene::Scene &scene, LoopState &loop,
                       io::PvdCollection &pvd, core::Model &model)
  {
    std::ifstream in(file, std::ios::binary);
    if (!in)
      throw scene::InputError(file.string() + ": no checkpoint to resume from");
    try
      {
        if (core::read_raw<std::uint64_t>(in) != checkpoint_magic)
          throw std::runtime_error("not a wirefem checkpoint");
        if (const auto version = core::read_raw<std::uint64_t>(in); version != checkpoint_version)
          throw std::runtime_error(
              fmt::format("checkpoint version {}, this wirefem reads {}", version, checkpoint_version));
        const auto size = core::read_raw<std::uint64_t>(in);
        const auto checksum = core::read_raw<std::uint64_t>(in);
        const auto at = in.tellg();
        in.seekg(0, std::ios::end);
        const auto available = static_cast<std::uint64_t>(in.tellg() - at);
        in.seekg(at);
        if (size != available)
          throw std::runtime_error(
              fmt::format("damaged: {} bytes of state where {} were written", available, size));
        std::string payload(size, '\0');
        in.read(payload.data(), static_cast<std::streamsize>(size));
        if (!in || fnv1a(payload) != checksum)
          throw std::runtime_error("damaged: its checksum does not match its contents");
        std::istringstream state(payload, std::ios::binary);
        std::string fp(core::read_raw<std::uint64_t>(state), ' ');
        state.read(fp.data(), static_cast<std::streamsize>(fp.size()));
        if (fp != scene.fingerprint)
          throw std::runtime_error("it was written for other scene parameters: " +
                                   first_difference(scene.fingerprint, fp));
        loop = core::read_raw<LoopState>(state);
        const auto n = core::read_raw<std::uint64_t>(state);
        for (std::uint64_t k = 0; k < n; ++k)
          {
            const auto time = core::read_raw<double>(state);
            std::string name(core::read_raw<std::uint64_t>(state), ' ');
            state.read(name.data(), static_cast<std::streamsize>(name.size()));
            pvd.add(time, name);
          }
        model.load(state);
        if (state.peek() != std::char_traits<char>::eof())
          throw std::runtime_error("damaged: state left over after the model");
        if (!model.finite() || !finite(loop) || !finite(model.energies()))
          throw std::runtime_error("damaged: the state read back is not finite");
      }
    catch (const std::runtime_error &e)
      {
        throw scene::InputError(file.string() + ": cannot resume: " + e.what());
      }
  }

  void check_output_place(const scene::Scene &scene, const RunOptions &options)
  {
    namespace fs = std::filesystem;
    const fs::path dir = scene.output.directory;
    const std::string where = dir.string() + ": Output/Directory: ";
    if (options.resume && options.replace)
      throw scene::InputError(where + "--resume and --replace exclude each other");
    if (options.resume && scene.setup != scene::Setup::injection)
      throw scene::InputError(where + "--resume: Set-up = cantilever and capstan write no checkpoint");
    std::error_code ec;
    for (fs::path p = dir; !p.empty(); p = p.parent_path())
      {
        if (fs::exists(p, ec) && !fs::is_directory(p, ec))
          throw scene::InputError(where + (p == dir ? std::string("is a file, not a directory")
                                                    : p.string() + " is a file, not a directory"));
        if (fs::exists(p, ec) || p == p.parent_path())
          break;
      }
    if (options.resume || options.replace)
      return;
    const auto files = run_files(dir);
    if (files.empty())
      return;
    if (fs::exists(dir / "checkpoint.bin", ec))
      throw scene::InputError(where + "holds an interrupted run (checkpoint.bin); --resume continues it, "
                                      "--replace deletes its files and starts over");
    throw scene::InputError(where + "holds an earlier run (" + files.front().filename().string() +
                            (files.size() > 1 ? fmt::format(" and {} more", files.size() - 1) : "") +
                            "); choose another directory, or --replace deletes its files and starts over");
  }

  void prepare_output_directory(const std::filesystem::path &dir, const bool replace)
  {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec)
      throw scene::InputError(dir.string() + ": Output/Directory: cannot be created: " + ec.message());
    if (replace)
      for (const auto &file : run_files(dir))
        if (!std::filesystem::remove(file, ec) && ec)
          throw scene::InputError(
              file.string() + ": Output/Directory: cannot delete the earlier run's file: " + ec.message());
  }
} // namespace wirefem::simulation
