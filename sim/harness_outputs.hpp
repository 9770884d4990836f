#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "common/error.hpp"
#include "common/output_file.hpp"
#include "cosim_core.hpp"

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

// A harness's main after its options: checks the output paths, then `run(model)`; a
// CosimFailure is reported as "NAME FAIL: ..." (exit 1), an rpu::Error as "NAME: ..."
// (exit 2); the model's waveforms are closed (renamed over their path) after a failure
// too, since they are what one debugs it with.
template <class Model, class Run>
int run_harness(std::string_view name, const std::string& trace, const std::string& vectors,
                std::unique_ptr<Model>& model, Run&& run) {
  int status = 0;
  try {
    check_output_paths(trace, vectors);
    status = run(model);
  } catch (const CosimFailure& e) {
    fmt::print(stderr, "{} FAIL: {}\n", name, e.what());
    status = 1;
  } catch (const Error& e) {
    fmt::print(stderr, "{}: {}\n", name, e.what());
    status = 2;
  }
  try {
    if (model) model->close_trace();
  } catch (const Error& e) {
    fmt::print(stderr, "{}: {}\n", name, e.what());
    status = 2;
  }
  return status;
}

}  // namespace rpu::sim
