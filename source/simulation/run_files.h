// The files of a run's output directory (docs/output.md): the checkpoint
// (its layout, checksum and what a resume checks) and the rules for a
// directory that already holds a run. Internal to the simulation module.
#pragma once

#include <wirefem/core/model.h>
#include <wirefem/io/vtu_writer.h>
#include <wirefem/scene/parameters.h>
#include <wirefem/simulation/simulation.h>

#include <cstdint>
#include <filesystem>

namespace wirefem::simulation
{
  /// What the run loop carries from step to step besides the model.
  struct LoopState
  {
    double next_row = 0.0;
    double next_vtu = 0.0;
    int vtu_count = 0;
    std::int32_t padding = 0; // written with the rest: no undefined bytes in the checkpoint
    // Running mean of the inlet force over the jamming window, in injected
    // length: a step that injects dL moves the mean by dL/window.
    double force_mean = 0.0;
    double previous_length = 0.0;
    double max_penetration = 0.0;
    double wall_time = 0.0; // spent before this process (resumed runs)
    std::uint64_t rows = 0; // of series.csv, written so far
  };
  static_assert(sizeof(LoopState) == 6 * sizeof(double) + 2 * sizeof(std::int32_t) + sizeof(std::uint64_t),
                "LoopState has padding");

  /// Written next to `file` and renamed over it, so an interruption while
  /// writing leaves the previous checkpoint intact.
  void write_checkpoint(const std::filesystem::path &file, const scene::Scene &scene, const LoopState &loop,
                        const io::PvdCollection &pvd, const core::Model &model);

  /// Reads a checkpoint into the loop state, the pvd entries and the model.
  /// Throws scene::InputError (naming the file) when it is missing, of
  /// another version, damaged (size, checksum, trailing bytes, a state that
  /// is not finite) or written for other scene parameters.
  void read_checkpoint(const std::filesystem::path &file, const scene::Scene &scene, LoopState &loop,
                       io::PvdCollection &pvd, core::Model &model);

  /// Before the model is built: the output directory is (or can become) a
  /// directory, and holds no earlier run unless the options say what to do
  /// with it (resume or replace). Writes nothing; throws scene::InputError.
  void check_output_place(const scene::Scene &scene, const RunOptions &options);

  /// Creates the output directory; with `replace`, deletes the earlier
  /// run's files in it (and no others). Throws scene::InputError.
  void prepare_output_directory(const std::filesystem::path &dir, bool replace);
} // namespace wirefem::simulation
