// Co-simulation of the RTL floating-point units against rpu::fp::soft, the golden
// model (docs/rtl.md). For one op and format, every vector (edge classes, constructed
// cases, then random operands from the generator the MPFR tests use) goes through the
// unit's valid/ready port with random stalls on both sides; each response is paired
// with its request by tag and compared bit for bit with the soft model. The first
// mismatch stops the run and prints op, format, operands, both results and the cycle.
//
//   fp_cosim --unit fma --format fp32 --op add [--count N] [--seed S]
//   fp_cosim --format fp16 --op div --count N --write-vectors FILE   (for the netlist)
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <ostream>
#include <functional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "cosim_core.hpp"
#include "fp/format.hpp"
#include "model.hpp"
#include "rpu/harness/fp_unit.hpp"
#include "harness_outputs.hpp"
#include "operands.hpp"
#include "oracle.hpp"
#include "rpu/spec.hpp"

namespace rpu::sim {
namespace {

using fp::Format;
using fp::Operands;

struct OpChoice {
  const spec::FpOpSpec* spec;      // the op code and unit (spec/fp_units.toml)
  const fp::oracle::OpInfo* info;  // the op as the operand generator knows it
};

OpChoice find_op(std::string_view name) {
  OpChoice choice{nullptr, nullptr};
  for (const spec::FpOpSpec& s : spec::kFpOps) {
    if (s.name == name) choice.spec = &s;
  }
  for (const fp::oracle::OpInfo& i : fp::oracle::all_ops()) {
    if (i.name == name) choice.info = &i;
  }
  if (choice.spec == nullptr || choice.info == nullptr) {
    // Built by appending: GCC 12 at -O3 warns (-Wrestrict) on "literal" + std::string.
    std::string message = "unknown op '";
    message.append(name).append("'; spec/fp_units.toml has");
    for (const spec::FpOpSpec& s : spec::kFpOps) message.append(" ").append(s.name);
    throw CLI::ValidationError("--op", message);
  }
  return choice;
}

// Operands as the format reads them: from_fp32 takes fp32 bits, from_int32 an int32.
Format input_format(fp::Op op, Format f) { return op == fp::Op::kFromFp32 ? fp::kFp32 : f; }
bool full_width_input(fp::Op op) { return op == fp::Op::kFromFp32 || op == fp::Op::kFromInt32; }

std::string describe_operand(fp::Op op, Format f, std::uint32_t bits) {
  char text[96];
  if (op == fp::Op::kFromInt32) {
    std::snprintf(text, sizeof text, "0x%08" PRIx32 " (%" PRId32 ")", bits, static_cast<std::int32_t>(bits));
  } else {
    const Format in = input_format(op, f);
    std::snprintf(text, sizeof text, "0x%0*" PRIx32 " (%.9g)", (in.width() + 3) / 4, bits,
                  fp::oracle::to_double(in, bits & in.all_bits()));
  }
  return text;
}

std::string describe_result(const fp::oracle::OpInfo& info, Format f, std::uint32_t bits) {
  char text[96];
  if (info.result == fp::oracle::Result::kBool) {
    std::snprintf(text, sizeof text, "0x%" PRIx32 " (%s)", bits, bits == 1 ? "true" : bits == 0 ? "false" : "not 0/1");
  } else if (info.result == fp::oracle::Result::kInt32) {
    std::snprintf(text, sizeof text, "0x%08" PRIx32 " (%" PRId32 ")", bits, static_cast<std::int32_t>(bits));
  } else {
    const Format out = info.op == fp::Op::kToFp32 ? fp::kFp32 : f;
    std::snprintf(text, sizeof text, "0x%0*" PRIx32 " (%.9g)", (out.width() + 3) / 4, bits,
                  fp::oracle::to_double(out, bits & out.all_bits()));
  }
  return text;
}

// Edge classes and constructed cases first (as tests/fp checks them against MPFR),
// then `count` random operand sets.
class VectorSource {
 public:
  VectorSource(const fp::oracle::OpInfo& info, Format f, std::int64_t count, std::uint64_t seed)
      : random_(info.op, f, seed), count_(count) {
    const std::vector<std::uint32_t> edges = fp::edge_values(input_format(info.op, f));
    if (info.op != fp::Op::kFromInt32) {
      for (std::uint32_t a : edges) {
        if (info.arity == 1) {
          fixed_.push_back({a, 0, 0});
          continue;
        }
        for (std::uint32_t b : edges) {
          if (info.arity == 2) {
            fixed_.push_back({a, b, 0});
            continue;
          }
          for (std::uint32_t c : edges) fixed_.push_back({a, b, c});
        }
      }
    }
    for (const Operands& v : fp::constructed(info.op, f)) fixed_.push_back(v);
  }

  std::int64_t size() const { return static_cast<std::int64_t>(fixed_.size()) + count_; }
  std::int64_t edge_count() const { return static_cast<std::int64_t>(fixed_.size()); }
  Operands at(std::int64_t i) {
    return i < edge_count() ? fixed_[static_cast<std::size_t>(i)] : random_.next();
  }

 private:
  std::vector<Operands> fixed_;
  fp::OperandSource random_;
  std::int64_t count_;
};

struct Pending {
  std::int64_t index;
  std::uint64_t accepted;  // cycle of the request transfer
  Operands operands;
  std::uint32_t expected;
  std::uint32_t tag;
};

struct Options {
  std::string unit, format, op, write_vectors, trace;
  std::int64_t count = 1'000'000;
  std::int64_t edge_limit = 0;
  std::uint64_t seed = 0;
  unsigned stall_percent = 6;
  bool quiet = false;
  bool check_config = false;
};

std::uint64_t default_seed(const Options& o) {
  std::string key = "cosim/";
  key.append(o.op).append("/").append(o.format);
  return std::hash<std::string>{}(key);
}

// The netlist testbench's input (sim/rpu_stream_netlist_tb.sv): a header "count", then one
// vector a line: the fp_req words (word 0 first, tag = the vector's index) and the
// fp_rsp words the model expects, in hex, so the testbench knows no field. With an
// edge limit, an even sample of the edge and constructed vectors is kept (a gate-level
// simulation is some thousand times slower than the Verilated RTL).
int write_vectors(const Options& o, const OpChoice& op, Format f) {
  VectorSource source(*op.info, f, o.count, o.seed);
  std::vector<std::int64_t> picked;
  const std::int64_t edges = source.edge_count();
  const std::int64_t stride = o.edge_limit > 0 ? std::max<std::int64_t>(1, (edges + o.edge_limit - 1) / o.edge_limit) : 1;
  for (std::int64_t i = 0; i < edges; i += stride) picked.push_back(i);
  for (std::int64_t i = edges; i < source.size(); ++i) picked.push_back(i);
  rpu::OutputFile file(o.write_vectors);
  std::ostream& out = file.stream();
  out << picked.size() << "\n";
  const std::uint32_t tag_mask = (std::uint64_t{1} << spec::kFpTagBits) - 1;
  char word[16];
  std::uint32_t tag = 0;
  for (const std::int64_t i : picked) {
    const Operands v = source.at(i);
    const streams::FpReq req{static_cast<std::uint32_t>(op.spec->op), tag, v.a, v.b, v.c};
    const streams::FpRsp rsp{tag, fp::soft_result(op.info->op, f, v)};
    for (const std::uint32_t w : req.pack()) {
      std::snprintf(word, sizeof word, "%08" PRIx32 " ", w);
      out << word;
    }
    for (const std::uint32_t w : rsp.pack()) {
      std::snprintf(word, sizeof word, " %08" PRIx32, w);
      out << word;
    }
    out << "\n";
    tag = (tag + 1) & tag_mask;
  }
  file.commit();
  std::printf("fp_cosim: wrote %zu vectors for %s %s to %s\n", picked.size(), o.op.c_str(),
              o.format.c_str(), o.write_vectors.c_str());
  return 0;
}

// spec/latencies.toml's [latency.<format>]: fpu for the fma and misc units, sfu for
// div, rcp and sqrt, rsq for rsqrt. The smallest latency of a run is the unit's (stalls
// only add).
int check_config(const Options& o, const OpChoice& op, std::uint64_t latency) {
  const char* field = op.spec->unit != "divsqrt" ? "fpu" : o.op == "rsqrt" ? "rsq" : "sfu";
  for (const auto& m : spec::kShaderLatencies) {
    if (m.format != o.format) continue;
    const int want = op.spec->unit != "divsqrt" ? m.value.fpu : o.op == "rsqrt" ? m.value.rsq : m.value.sfu;
    const bool ok = static_cast<std::uint64_t>(want) == latency;
    std::printf("%s [latency.%s] %s = %d; RTL %s latency %" PRIu64 "\n", ok ? "ok  " : "FAIL", o.format.c_str(),
                field, want, o.op.c_str(), latency);
    if (ok) return 0;
    std::fprintf(stderr, "cosim FAIL: spec/latencies.toml disagrees with the RTL's measured latency; set "
                         "[latency.%s] %s to the RTL's number above\n", o.format.c_str(), field);
    return 1;
  }
  std::fprintf(stderr, "cosim FAIL: spec/latencies.toml has no [latency.%s]; the RTL's %s latency is %" PRIu64 "\n",
               o.format.c_str(), field, latency);
  return 1;
}

// `model` outlives the run, so that its waveforms are closed also after a failure.
int run(const Options& o, const OpChoice& op, Format f, std::unique_ptr<Model<harness::FpUnit>>& model) {
  if (op.spec->unit != o.unit) {
    std::fprintf(stderr, "fp_cosim: op %s runs on the %.*s unit, not %s (spec/fp_units.toml)\n", o.op.c_str(),
                 static_cast<int>(op.spec->unit.size()), op.spec->unit.data(), o.unit.c_str());
    return 2;
  }
  const ModelInfo* info = find_model<harness::FpUnit>({{"unit", o.unit}, {"format", o.format}});
  if (!info) {
    std::fprintf(stderr, "fp_cosim: no model for unit %s in format %s; built: %s\n", o.unit.c_str(), o.format.c_str(),
                 built_models<harness::FpUnit>().c_str());
    return 2;
  }
  model = make_model<harness::FpUnit>(*info, o.seed, o.trace);

  VectorSource source(*op.info, f, o.count, o.seed);
  Stalls stalled(o.seed ^ 0x5bd1e995u, o.stall_percent / 100.0);
  std::mt19937_64& rng = stalled.rng();  // also the junk in ignored bits
  const std::uint32_t tag_mask = (std::uint64_t{1} << spec::kFpTagBits) - 1;
  const std::uint32_t high_bits = ~f.all_bits();
  const auto op_code = static_cast<std::uint32_t>(op.spec->op);

  Clock clock(*model);
  harness::FpUnit::Inputs in;
  clock.reset(in);

  PendingByTag<Pending> pending("fp_req", "fp_rsp", spec::kFpTagBits);
  Watchdog watchdog(1000);  // cycles without a response while one is owed
  std::int64_t next = 0, checked = 0;
  std::uint64_t cycles = 0;
  std::uint64_t min_latency = ~std::uint64_t{0}, max_latency = 0;
  Operands current{};
  std::uint32_t current_expected = 0;
  bool have_current = false;
  const auto start = std::chrono::steady_clock::now();
  const auto vector_name = [&](const Pending& p) {
    return "vector " + std::to_string(p.index) + (p.index < source.edge_count() ? " (edge/constructed)" : " (random)");
  };

  try {
    while (checked < source.size()) {
      const std::uint64_t cycle = clock.cycle();
      if (!have_current && next < source.size()) {
        current = source.at(next);
        current_expected = fp::soft_result(op.info->op, f, current);
        have_current = true;
        // Bits the unit must ignore get random values: the operands beyond the arity and,
        // for format operands, everything above the format's width.
        const std::uint32_t junk = full_width_input(op.info->op) ? 0 : high_bits;
        in.req.a = current.a | (static_cast<std::uint32_t>(rng()) & junk);
        in.req.b = op.info->arity >= 2 ? current.b | (static_cast<std::uint32_t>(rng()) & junk) : static_cast<std::uint32_t>(rng());
        in.req.c = op.info->arity >= 3 ? current.c | (static_cast<std::uint32_t>(rng()) & junk) : static_cast<std::uint32_t>(rng());
        in.req.op = op_code;
        in.req.tag = static_cast<std::uint32_t>(next) & tag_mask;
      }
      in.req_valid = have_current && !stalled();
      in.rsp_ready = !stalled();
      const harness::FpUnit::Outputs out = clock.settle(in);

      if (out.rsp_valid && in.rsp_ready) {
        const Pending p = pending.take(out.rsp.tag);
        const std::string mismatch = field_mismatch(streams::FpRsp{p.tag, p.expected}, out.rsp);
        if (!mismatch.empty()) {
          std::fprintf(stderr, "cosim FAIL: unit %s, op %s, format %s (%s), cycle %" PRIu64 ", %s\n", o.unit.c_str(),
                       o.op.c_str(), o.format.c_str(), f.name().c_str(), cycle, vector_name(p).c_str());
          const std::uint32_t operands[] = {p.operands.a, p.operands.b, p.operands.c};
          for (int i = 0; i < op.info->arity; ++i) {
            std::fprintf(stderr, "  %c = %s\n", 'a' + i, describe_operand(op.info->op, f, operands[i]).c_str());
          }
          std::fprintf(stderr, "  expected (soft) %s tag 0x%02" PRIx32 "\n  actual   (rtl)  %s tag 0x%02" PRIx32 "\n  %s\n",
                       describe_result(*op.info, f, p.expected).c_str(), p.tag,
                       describe_result(*op.info, f, out.rsp.result).c_str(), out.rsp.tag, mismatch.c_str());
          return 1;
        }
        const std::uint64_t latency = cycle - p.accepted;
        min_latency = std::min(min_latency, latency);
        max_latency = std::max(max_latency, latency);
        ++checked;
        watchdog.progress(cycle);
      }
      if (in.req_valid && out.req_ready) {
        pending.add(in.req.tag, {next, cycle, current, current_expected, in.req.tag});
        have_current = false;
        ++next;
      }
      watchdog.check(cycle, !pending.empty(), [&] {
        return std::to_string(pending.size()) + " requests outstanding (oldest: " + vector_name(pending.oldest()) + ")";
      });
      clock.tick();
    }
    harness::FpUnit::Inputs idle = in;
    idle.req_valid = false;
    idle.rsp_ready = true;
    cycles = clock.cycle();  // the run's, without the quiet cycles below
    expect_quiet(clock, idle, 64, [](const harness::FpUnit::Outputs& out) {
      return out.rsp_valid ? "an fp_rsp (tag " + hex(out.rsp.tag, spec::kFpTagBits) + ")" : std::string();
    });
  } catch (const CosimFailure& e) {
    std::fprintf(stderr, "cosim FAIL: %s %s: %s\n", o.op.c_str(), o.format.c_str(), e.what());
    return 1;
  }

  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("cosim ok: unit %s, op %s, format %s (%s): %" PRId64 " vectors (%" PRId64
              " edge/constructed) match soft in %" PRIu64 " cycles, %.2f s (%.0f vectors/s, %.0f cycles/s); "
              "latency %" PRIu64 "..%" PRIu64 " cycles with %u%% stalls\n",
              o.unit.c_str(), o.op.c_str(), o.format.c_str(), f.name().c_str(), checked, source.edge_count(),
              cycles, seconds, static_cast<double>(checked) / seconds,
              static_cast<double>(cycles) / seconds, min_latency, max_latency, o.stall_percent);
  return o.check_config ? check_config(o, op, min_latency) : 0;
}

}  // namespace
}  // namespace rpu::sim

int main(int argc, char** argv) {
  using namespace rpu::sim;
  Options o;
  CLI::App app{"Co-simulate an RTL floating-point unit against rpu::fp::soft"};
  app.add_option("--unit", o.unit, "unit (spec/fp_units.toml); required unless --write-vectors");
  app.add_option("--format", o.format, "format name (spec/formats.toml)")->required();
  app.add_option("--op", o.op, "op name (spec/fp_units.toml)")->required();
  app.add_option("--count", o.count, "random vectors after the edge and constructed ones")->check(CLI::NonNegativeNumber);
  app.add_option("--seed", o.seed, "operand, stall and register-initialisation seed (default: from op and format)");
  app.add_option("--stall-percent", o.stall_percent, "percent of cycles without req valid / rsp ready")
      ->check(CLI::Range(0, 90));
  app.add_option("--write-vectors", o.write_vectors, "write vectors and the model's results for the netlist testbench");
  app.add_option("--edge-limit", o.edge_limit, "with --write-vectors: at most this many edge vectors (0: all)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--trace", o.trace, "write an FST waveform to this file");
  app.add_flag("--check-config", o.check_config,
               "fail unless spec/latencies.toml's [latency.FORMAT] equals the measured latency");
  CLI11_PARSE(app, argc, argv);
  try {
    check_output_paths(o.trace, o.write_vectors);
    const OpChoice op = find_op(o.op);
    const rpu::fp::Format f = rpu::fp::format_by_name(o.format);
    if (o.seed == 0) o.seed = default_seed(o);
    if (!o.write_vectors.empty()) return write_vectors(o, op, f);
    if (o.unit.empty()) {
      std::fprintf(stderr, "fp_cosim: --unit is required to co-simulate\n");
      return 2;
    }
    std::unique_ptr<Model<harness::FpUnit>> model;
    const int status = run(o, op, f, model);
    if (model) model->close_trace();
    return status;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fp_cosim: %s\n", e.what());
    return 2;
  }
}
