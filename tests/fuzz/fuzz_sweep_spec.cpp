// libFuzzer target: rpu::sweep::parse_spec on arbitrary text, the reader of `rpu sweep
// FILE.toml`, with paths resolved against the source tree (its scenes and configurations
// exist). It either returns a sweep whose every point names an existing reference and
// has a unique id, or throws rpu::Error.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <set>
#include <string_view>

#include "common/error.hpp"
#include "sweep/sweep_spec.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  rpu::sweep::Spec spec;
  try {
    spec = rpu::sweep::parse_spec(text, "fuzz.toml", RPU_SOURCE_DIR);
  } catch (const rpu::Error&) {
    return 0;
  }
  std::set<std::string> ids, references;
  for (const rpu::sweep::Point& r : spec.references) {
    if (r.fidelity != "reference" || !ids.insert(r.id).second) std::abort();
    references.insert(r.id);
  }
  for (const rpu::sweep::Point& p : spec.points) {
    if (!ids.insert(p.id).second || !references.contains(p.reference) || p.format.empty()) std::abort();
  }
  return 0;
}
