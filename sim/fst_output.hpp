#pragma once

#include <verilated_fst_c.h>

#include <cstdint>
#include <fstream>
#include <string>

#include "common/output_file.hpp"
#include "gtkwave/fstapi.h"

namespace rpu::sim {

// Why an FST file is not whole, or "" if it is: a header block first, whole blocks of
// known kinds to the end (fstapi.h: a kind byte, then a big-endian length that counts
// itself), the geometry and hierarchy the writer adds when it closes, and the header's
// end time equal to `end_time`. FST's own reader loops forever on some truncated files,
// so this walks the block headers itself.
inline std::string fst_problem(const std::string& path, std::uint64_t end_time) {
  std::ifstream in(path, std::ios::binary);
  in.seekg(0, std::ios::end);
  const auto size = static_cast<std::uint64_t>(in.tellg());
  const auto be64 = [](const unsigned char* b) {
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v = v << 8 | b[i];
    return v;
  };
  bool geometry = false, hierarchy = false;
  for (std::uint64_t at = 0; at < size;) {
    unsigned char head[9 + 16];
    const std::uint64_t want = at == 0 ? sizeof head : 9;
    if (size - at < want || !in.seekg(static_cast<std::streamoff>(at)) ||
        !in.read(reinterpret_cast<char*>(head), static_cast<std::streamsize>(want))) {
      return "it ends inside a block header at byte " + std::to_string(at);
    }
    const unsigned kind = head[0];
    const std::uint64_t length = be64(head + 1);
    if (at == 0 && kind != FST_BL_HDR) return "it does not start with an FST header";
    if (kind > FST_BL_VCDATA_DYN_ALIAS2) return "an unfinished block (kind " + std::to_string(kind) + ") at byte " +
                                                std::to_string(at);
    if (length < 8 || length > size - at - 1) return "the block at byte " + std::to_string(at) + " runs past the end";
    if (at == 0 && be64(head + 17) != end_time) {
      return "its header ends at time " + std::to_string(be64(head + 17)) + ", expected " + std::to_string(end_time);
    }
    geometry |= kind == FST_BL_GEOM;
    hierarchy |= kind == FST_BL_HIER || kind == FST_BL_HIER_LZ4 || kind == FST_BL_HIER_LZ4DUO;
    at += 1 + length;
  }
  if (!geometry || !hierarchy) return "the writer's closing geometry and hierarchy blocks are missing";
  return "";
}

// FST waveforms of a Verilated top through an OutputFile: the writer fills a temporary
// beside the --trace path, and close() renames it over the path only once it is whole
// (fst_problem). The writer ignores its own write errors, so this check is the one
// that catches a full disk.
class FstOutput {
 public:
  // rpu::Error naming the path if the writer cannot create the file. The context must
  // have traceEverOn(true).
  template <class Top>
  FstOutput(Top& top, const std::string& path) : file_(path) {
    // The writer keeps its hierarchy in "<file>.hier" until it closes.
    file_.add_sidecar(file_.temp_path().string() + ".hier");
    top.trace(&fst_, 99);
    fst_.open(file_.temp_path().c_str());
    if (!fst_.isOpen()) file_.fail("the FST writer cannot create it");
  }

  void dump(std::uint64_t time) {
    fst_.dump(time);
    last_ = time;
  }

  // Closes the writer, checks the file and renames it over the path; rpu::Error naming
  // the path if it is not whole.
  void close() {
    fst_.close();
    const std::string problem = fst_problem(file_.temp_path().string(), last_);
    if (!problem.empty()) file_.fail(problem);
    file_.commit();
  }

 private:
  OutputFile file_;  // declared first: removed after the writer has closed
  VerilatedFstC fst_;
  std::uint64_t last_ = 0;
};

}  // namespace rpu::sim
