#pragma once

#include <filesystem>
#include <string>

#include "common/error.hpp"
#include "common/output_file.hpp"

namespace rpu::sim {

// The co-simulation harnesses' --trace and --write-vectors paths, checked before the
// run so that a bad path does not cost a long co-simulation; empty: not asked for.
inline void check_output_paths(const std::string& trace, const std::string& vectors) {
  if (!trace.empty()) {
    if (std::filesystem::path(trace).extension() != ".fst") {
      throw Error(trace + ": --trace writes FST waveforms; give a file name ending in .fst");
    }
    check_output_path(trace);
  }
  if (!vectors.empty()) check_output_path(vectors);
}

}  // namespace rpu::sim
