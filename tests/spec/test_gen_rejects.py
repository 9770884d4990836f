"""spec/gen.py refuses tables that break the spec's rules and names the file."""
import pathlib
import shutil
import subprocess
import sys
import tempfile

spec = pathlib.Path(sys.argv[1])
cases = {
    "exponent too wide": ("formats.toml", "exponent_bits = 8\nfraction_bits = 23", "exponent_bits = 9\nfraction_bits = 23"),
    "unknown config format": ("configs.toml", 'format = "rpu24"', 'format = "fp99"'),
    "chunk does not divide threads": ("configs.toml", "chunk_size = 2", "chunk_size = 3"),
    "kd node word not 32 bits": ("memory_map.toml", "index_bits = 30", "index_bits = 29"),
    "field past its record": ("memory_map.toml", "camera]\nbytes = 64", "camera]\nbytes = 56"),
    "misaligned field": ("memory_map.toml", "a_at = 0 ", "a_at = 2 "),
    "section alignment not a power of two": ("memory_map.toml", "section_alignment = 64", "section_alignment = 48"),
    "duplicate opcode": ("isa.toml", "opcode = 0x03", "opcode = 0x02"),
    "overlapping encoding fields": ("isa.toml", "wmask = [13, 4]", "wmask = [12, 4]"),
    "unknown operand kind": ("isa.toml", 'operands = ["d", "a", "b", "c"]', 'operands = ["d", "a", "q"]'),
    "sources other than positional": ("isa.toml", 'mods = "float"\nsources = "positional"', 'mods = "float"\nsources = "lanewise"'),
    "positional sources without a destination": ("isa.toml", 'operands = ["a"]\nclass = "mem"\nmods = "none"\n',
                                                 'operands = ["a"]\nclass = "mem"\nmods = "none"\nsources = "positional"\n'),
    "unknown latency class": ("isa.toml", 'class = "sfu"', 'class = "fancy"'),
    "spin counting an instruction that writes": ("isa.toml", 'pc_only = ["bra", "bz", "bnz"]',
                                                 'pc_only = ["bra", "bz", "bnz", "call"]'),
    "operand without its field": ("isa.toml", 'format = "R"\noperands = ["d", "a", "b", "c"]', 'format = "I"\noperands = ["d", "a", "b", "c"]'),
    "more registers than the encoding names": ("configs.toml", "registers = 32", "registers = 65"),
    "unknown config key": ("configs.toml", "shader_cores = 4", "shader_cores = 4\nshader_core = 4"),
    "missing config key": ("configs.toml", "clock_mhz = 100\n", ""),
    "config value out of range": ("configs.toml", "shader_cores = 4", "shader_cores = 0"),
    "cache line not a power of two": ("configs.toml", "line_bytes = 64", "line_bytes = 48"),
    "cache sets not a power of two": ("configs.toml", "bytes = 32768", "bytes = 24576"),
    "a measured latency in a config": ("configs.toml", "[config.dram]", "[config.iu]\nwoop = 3\n\n[config.dram]"),
    "latency table without a field": ("latencies.toml", "pop = 4\n", ""),
    "latency table of an unknown format": ("latencies.toml", "[tu.rpu24]", "[tu.rpu99]"),
    "derived value of an unknown key": ("config_keys.toml", 'expr = "shader_cores * threads_per_core"',
                                        'expr = "shader_cores * thread_per_core"'),
    "expression outside the language": ("config_keys.toml", 'expr = "shader_cores * threads_per_core"',
                                        'expr = "shader_cores ** threads_per_core"'),
    "fp op not in the soft model": ("fp_units.toml", '"fract"]', '"fract", "cbrt"]'),
    "fp op in two units": ("fp_units.toml", '"div", "rcp"', '"div", "add"'),
    "stream width of an unknown constant": ("streams.toml", 'width = "RayTagBits", doc = "the ray\'s tag"',
                                            'width = "RayTagBitz", doc = "the ray\'s tag"'),
    "stream vector of 8-bit words": ("streams.toml", 'width = 32, count = 3, doc = "x, y, z (fp32)"',
                                     'width = 8, count = 3, doc = "x, y, z (fp32)"'),
    "stream scalar wider than a word": ("streams.toml", '{ name = "t_min", width = 32,', '{ name = "t_min", width = 33,'),
    "stream width not exact": ("streams.toml", 'count = "MemLineBytes / 4"', 'count = "MemLineBytes / 3"'),
    "duplicate stream field": ("streams.toml", '{ name = "prim", width = 32, doc = "the hit triangle\'s index" },\n  { name = "nodes"',
                               '{ name = "prim", width = 32, doc = "the hit triangle\'s index" },\n  { name = "prim"'),
    "more threads than a thread field names": ("streams.toml", "thread_bits = { value = 8,", "thread_bits = { value = 4,"),
    "a chunk wider than the issue record's lanes": ("streams.toml", "chunk_lanes = { value = 8,", "chunk_lanes = { value = 2,"),
    "more faults than the fault kind names": ("streams.toml", "fault_kind_bits = { value = 4,", "fault_kind_bits = { value = 3,"),
    "a fault without a doc": ("isa.toml", 'name = "watchdog"\ndoc =', 'name = "watchdog"\ndocs ='),
    "a cache line other than the memory port's": ("streams.toml", "dram_line_bytes = { value = 64,", "dram_line_bytes = { value = 32,"),
    "more miss registers than a memory tag names": ("streams.toml", "dram_mshr_bits = { value = 4,", "dram_mshr_bits = { value = 2,"),
    "more caches than a memory tag names": ("streams.toml", "dram_mshr_bits = { value = 4,", "dram_mshr_bits = { value = 6,"),
}
failures = 0
for what, (table, old, new) in cases.items():
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        for f in spec.glob("*.toml"):
            shutil.copy(f, tmp)
        text = (tmp / table).read_text()
        assert old in text, f"test setup: '{old}' not in {table}"
        (tmp / table).write_text(text.replace(old, new, 1))
        r = subprocess.run([sys.executable, spec / "gen.py", "--spec-dir", tmp,
                            "--cpp", tmp / "o.hpp", "--sv", tmp / "o.sv"],
                           capture_output=True, text=True)
        ok = r.returncode != 0 and table in r.stderr and not (tmp / "o.hpp").exists()
        print(f"{'ok  ' if ok else 'FAIL'} {what}: exit {r.returncode}: {r.stderr.strip()}")
        failures += not ok
sys.exit(1 if failures else 0)
