#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "asm/assembler.hpp"
#include "common/error.hpp"

// Assembly sources held in memory, through the assembler's SourceLoader: tests name
// their files (main.s, lib/a.s) and see which paths the assembler asked for.
namespace rpu::isa::test {

struct MemorySources {
  std::map<std::string, std::string> files;
  std::vector<std::string> requested;

  SourceLoader loader() {
    return [this](const std::filesystem::path& p) -> std::optional<std::string> {
      requested.push_back(p.generic_string());
      const auto it = files.find(p.generic_string());
      if (it == files.end()) return std::nullopt;
      return it->second;
    };
  }

  Firmware assemble(const std::string& main = "main.s") { return isa::assemble(main, loader()); }
};

inline Firmware assemble_text(const std::string& text) {
  MemorySources sources;
  sources.files["main.s"] = text;
  return sources.assemble();
}

// The message of the rpu::Error that assembling `text` throws ("" and a test failure
// if it assembles).
inline std::string assembly_error(const std::string& text, MemorySources sources = {}) {
  sources.files["main.s"] = text;
  try {
    sources.assemble();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "assembled without error:\n" << text;
  return "";
}

}  // namespace rpu::isa::test
