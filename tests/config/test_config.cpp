// Run-time hardware configurations (docs/configurations.md): named ones resolve to what
// spec/gen.py resolved, files and --set change them, and every bad key or value gets a
// message naming where it came from.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "config/config.hpp"
#include "rpu/spec.hpp"

namespace rpu::config {
namespace {

class ConfigFile : public testing::Test {
 protected:
  std::filesystem::path dir_ = std::filesystem::path(testing::TempDir()) /
                               ("rpu_config_" + std::string(testing::UnitTest::GetInstance()->current_test_info()->name()));
  void SetUp() override { std::filesystem::create_directories(dir_); }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) const {
    const std::filesystem::path p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }
};

std::string error_of(std::string_view config, std::vector<std::string> sets = {}) {
  try {
    resolve(config, sets);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

// Python (gen.py) resolved the named configurations at build time, C++ resolves them at
// run time: both evaluate the same expressions and pick the same latencies.
TEST(Config, NamedConfigurationsResolveAsTheGeneratorResolvedThem) {
  for (const spec::HardwareConfig& named : spec::kConfigs) {
    const spec::HardwareConfig c = resolve(named.name);
    const std::vector<Entry> want = entries(named), got = entries(c);
    ASSERT_EQ(want.size(), got.size());
    for (std::size_t i = 0; i < want.size(); ++i) {
      EXPECT_EQ(want[i].name, got[i].name);
      EXPECT_EQ(want[i].value, got[i].value) << named.name << ": " << want[i].name;
    }
  }
}

TEST(Config, SetChangesAKeyAndTheValuesDerivedFromIt) {
  const spec::HardwareConfig c = resolve("default", {"shader_cores=8", "node_cache.bytes=65536"});
  EXPECT_EQ(c.shader_cores, 8);
  EXPECT_EQ(c.threads, 8 * c.threads_per_core);
  EXPECT_EQ(c.node_cache.bytes, 65536);
  EXPECT_EQ(c.node_cache.sets, 65536 / (c.node_cache.line_bytes * c.node_cache.ways));
  EXPECT_EQ(c.node_cache.index_bits, 8);
  // Later sets win.
  EXPECT_EQ(resolve("tiny", {"shader_cores=2", "shader_cores=3"}).shader_cores, 3);
}

TEST(Config, TheFormatPicksTheMeasuredLatencies) {
  const spec::HardwareConfig rpu24 = resolve("default", {"format=rpu24"});
  EXPECT_EQ(rpu24.latency_format, "rpu24");
  EXPECT_EQ(rpu24.tu_format, "rpu24");
  EXPECT_EQ(rpu24.tu.setup_woop, spec::kConfigs[2].tu.setup_woop);
  // fp16's shader latencies are measured, its ray units' are not: they come from the
  // narrowest measured format at least as wide, rpu24.
  const spec::HardwareConfig fp16 = resolve("default", {"format=fp16"});
  EXPECT_EQ(fp16.latency_format, "fp16");
  EXPECT_EQ(fp16.tu_format, "rpu24");
  EXPECT_EQ(fp16.iu_format, "rpu24");
  // E8M20 lies between rpu24 (16 bits) and fp32 (23): fp32 bounds it.
  const spec::HardwareConfig e8m20 = resolve("default", {"format=E8M20"});
  EXPECT_EQ(e8m20.latency_format, "fp32");
  EXPECT_EQ(e8m20.tu_format, "fp32");
}

TEST(Config, SetMessagesNameTheSetAndTheNearestKey) {
  EXPECT_EQ(error_of("default", {"shader_core=8"}),
            "--set shader_core=8: unknown key 'shader_core' (did you mean 'shader_cores'?)");
  EXPECT_EQ(error_of("default", {"node_cache.byte=4096"}),
            "--set node_cache.byte=4096: unknown key 'node_cache.byte' (did you mean 'node_cache.bytes'?)");
  EXPECT_EQ(error_of("default", {"frobnicate=1"}), "--set frobnicate=1: unknown key 'frobnicate'");
  EXPECT_EQ(error_of("default", {"shader_cores"}), "--set shader_cores: expected key=value");
  EXPECT_EQ(error_of("default", {"shader_cores=eight"}), "--set shader_cores=eight: 'eight' is not an integer");
  EXPECT_EQ(error_of("default", {"shader_cores=8x"}), "--set shader_cores=8x: '8x' is not an integer");
  EXPECT_EQ(error_of("default", {"shader_cores=0"}),
            "--set shader_cores=0: shader_cores = 0 is outside [1, 256] (shader cores on the chip)");
  EXPECT_EQ(error_of("default", {"shader_cores=99999999999999999999"}),
            "--set shader_cores=99999999999999999999: 99999999999999999999 is outside [1, 256]");
  EXPECT_EQ(error_of("default", {"data_cache.line_bytes=48"}),
            "--set data_cache.line_bytes=48: data_cache.line_bytes = 48 is not a power of two (line size)");
  EXPECT_EQ(error_of("default", {"threads=64"}),
            "--set threads=64: 'threads' is derived (threads = shader_cores * threads_per_core), not a choice");
  EXPECT_EQ(error_of("default", {"iu.woop=3"}),
            "--set iu.woop=3: 'iu.woop' is measured on the RTL (spec/latencies.toml, by the format), not a choice");
  EXPECT_NE(error_of("default", {"format=fp99"}).find("--set format=fp99: "), std::string::npos);
}

TEST(Config, RulesNameEveryValueAndWhereItCameFrom) {
  EXPECT_EQ(error_of("default", {"threads_per_core=30"}),
            "configuration 'default': chunk_size must divide threads_per_core (threads_per_core = 30 from --set "
            "threads_per_core=30, chunk_size = 4 from config 'default')");
  EXPECT_EQ(error_of("default", {"node_cache.bytes=24576"}),
            "configuration 'default': node_cache must have a power-of-two number of sets (node_cache.bytes / "
            "(node_cache.line_bytes * node_cache.ways)) (node_cache.sets = 96)");
  EXPECT_EQ(error_of("default", {"registers=65"}),
            "configuration 'default': registers must be at most what the ISA's register fields name (registers = "
            "65 from --set registers=65)");
}

TEST(Config, UnknownNameIsNeitherANamedConfigurationNorAFile) {
  EXPECT_EQ(error_of("defualt"),
            "--config defualt: no such configuration file, and no named configuration 'defualt' (spec/configs.toml "
            "has tiny, default, rpu2005, drpu) (did you mean 'default'?)");
}

TEST_F(ConfigFile, AFileWithEveryKeyIsAConfiguration) {
  // What `rpu config show` prints reads back to the same configuration.
  const spec::HardwareConfig want = resolve("rpu2005", {"shader_cores=3", "dram.banks=16"});
  const std::string file = write("mine.toml", to_toml(want));
  const spec::HardwareConfig got = resolve(file);
  EXPECT_EQ(got.name, want.name);
  const std::vector<Entry> a = entries(want), b = entries(got);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].value, b[i].value) << a[i].name;
}

TEST_F(ConfigFile, ABaseAndChanges) {
  const std::string file = write("small.toml", "base = \"default\"\nshader_cores = 2\n\n[node_cache]\nbytes = 8192\n");
  const spec::HardwareConfig c = resolve(file, {"data_cache.bytes=4096"});
  EXPECT_EQ(c.name, "small");
  EXPECT_EQ(c.shader_cores, 2);
  EXPECT_EQ(c.node_cache.bytes, 8192);
  EXPECT_EQ(c.node_cache.sets, 32);
  EXPECT_EQ(c.data_cache.bytes, 4096);
  EXPECT_EQ(c.threads_per_core, spec::kConfigs[1].threads_per_core);
  // Dotted keys are the same keys.
  EXPECT_EQ(resolve(write("dotted.toml", "base = \"tiny\"\nnode_cache.ways = 4\n")).node_cache.ways, 4);
}

// The line and column are those of the value.
TEST_F(ConfigFile, MessagesNameTheFileLineAndColumn) {
  const std::string typo = write("typo.toml", "base = \"default\"\n\n[node_cache]\nbites = 8192\n");
  EXPECT_EQ(error_of(typo), typo + ":4:9: unknown key 'node_cache.bites' (did you mean 'node_cache.bytes'?)");
  const std::string range = write("range.toml", "base = \"default\"\nclock_mhz = 0\n");
  EXPECT_EQ(error_of(range), range + ":2:13: clock_mhz = 0 is outside [1, 100000] (the chip's clock)");
  const std::string type = write("type.toml", "base = \"default\"\nshader_cores = \"four\"\n");
  EXPECT_EQ(error_of(type), type + ":2:16: shader_cores must be an integer");
  const std::string fmt = write("format.toml", "base = \"default\"\nformat = 16\n");
  EXPECT_EQ(error_of(fmt), fmt + ":2:10: format must be a string (a format name)");
  const std::string syntax = write("syntax.toml", "base = \"default\"\nshader_cores = = 4\n");
  EXPECT_EQ(error_of(syntax).rfind(syntax + ":2:", 0), 0u) << error_of(syntax);
  const std::string twice = write("twice.toml", "base = \"default\"\nshader_cores = 4\nshader_cores = 8\n");
  EXPECT_EQ(error_of(twice).rfind(twice + ":3:", 0), 0u) << error_of(twice);
  const std::string base = write("base.toml", "base = \"defualt\"\n");
  EXPECT_EQ(error_of(base), base + ":1:8: base = \"defualt\" is not a named configuration (spec/configs.toml has "
                                   "tiny, default, rpu2005, drpu) (did you mean 'default'?)");
  const std::string measured = write("measured.toml", "base = \"default\"\n[tu]\ninner = 1\n");
  EXPECT_EQ(error_of(measured),
            measured + ":3:9: 'tu.inner' is measured on the RTL (spec/latencies.toml, by the format), not a choice");
}

TEST_F(ConfigFile, AFileWithoutABaseMustHoldEveryKey) {
  const std::string file = write("partial.toml", "shader_cores = 2\n");
  const std::string e = error_of(file);
  EXPECT_EQ(e.rfind(file + ": missing threads_per_core, chunk_size, ", 0), 0u) << e;
  EXPECT_NE(e.find("dram.bank_busy"), std::string::npos) << e;
}

TEST_F(ConfigFile, RulesNameTheFileLine) {
  const std::string file = write("chunks.toml", "base = \"default\"\nthreads_per_core = 6\n");
  EXPECT_EQ(error_of(file), "configuration 'chunks': chunk_size must divide threads_per_core (threads_per_core = 6 "
                            "from " + file + ":2:20, chunk_size = 4 from config 'default')");
}

}  // namespace
}  // namespace rpu::config
