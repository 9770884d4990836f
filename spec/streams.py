"""The streams of spec/streams.toml: their layout, the SV structs, the C++ structs with
pack/unpack, and docs/streams.md (gen.py calls these; docs/rtl.md, "Streams").

A stream is an SV packed struct: its first field is the most significant. The C++ side
holds a stream as 32-bit words, bit k of the struct in bit k % 32 of word k / 32, which
is how Verilator stores a port of that width, so a Verilated top's flat port is copied
word by word and never by field.
"""
from __future__ import annotations

import ast
import re

from names import camel

IDENT = re.compile(r"^[a-z][a-z0-9_]*$")
WHERE = "spec/streams.toml"


class StreamError(Exception):
    pass


def base_constants(spec: dict, fp_op_bits: int) -> dict[str, int]:
    """The spec constants a width may name, by their rpu_pkg names (gen.py's gen_sv)."""
    env = {}
    for section, table in spec["memory_map"].items():
        for key, value in table.items():
            if isinstance(value, int):
                env[camel(section) + camel(key)] = value
    for name, value in spec["isa"]["encoding"].items():
        if name == "word_bits":
            env["IsaWordBits"] = value
        else:
            env[f"Isa{camel(name)}Lsb"], env[f"Isa{camel(name)}Width"] = value
    for c in spec["configs"]["config"]:
        for key, value in c.items():
            if isinstance(value, int):
                env[f"Config{camel(c['name'])}{camel(key)}"] = value
    port = spec["fp_units"]["port"]
    env.update(FpOperandBits=port["operand_bits"], FpTagBits=port["tag_bits"], FpOpBits=fp_op_bits)
    return env


def evaluate(text, env: dict[str, int], where: str) -> int:
    """An integer, a constant's name or an expression of them (+ - * / << ( ) max clog2)."""
    if isinstance(text, int) and not isinstance(text, bool):
        return text
    if not isinstance(text, str):
        raise StreamError(f"{where}: {text!r} is neither an integer nor an expression")

    def ev(node) -> int:
        if isinstance(node, ast.Constant) and isinstance(node.value, int):
            return node.value
        if isinstance(node, ast.Name):
            if node.id not in env:
                raise StreamError(f"{where}: unknown constant '{node.id}' in '{text}'")
            return env[node.id]
        if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Sub, ast.Mult, ast.Div, ast.LShift)):
            a, b = ev(node.left), ev(node.right)
            if isinstance(node.op, ast.LShift):
                return a << b
            if isinstance(node.op, ast.Div):
                if b == 0 or a % b:
                    raise StreamError(f"{where}: '{text}' divides {a} by {b}, which is not exact")
                return a // b
            return a + b if isinstance(node.op, ast.Add) else a - b if isinstance(node.op, ast.Sub) else a * b
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and not node.keywords:
            args = [ev(a) for a in node.args]
            if node.func.id == "max" and args:
                return max(args)
            if node.func.id == "clog2" and len(args) == 1 and args[0] > 0:
                return (args[0] - 1).bit_length()
        raise StreamError(f"{where}: '{text}' is not an expression of + - * / << max() clog2()")

    try:
        tree = ast.parse(text, mode="eval")
    except SyntaxError as e:
        raise StreamError(f"{where}: '{text}': {e.msg}") from e
    return ev(tree.body)


def layout(spec: dict, fp_op_bits: int) -> dict:
    """{"constants": [(Name, value, source, doc)], "streams": [stream]}; a stream is
    {name, doc, bits, fields: [{name, width, count, lsb, bits, sv_type, width_src,
    count_src, doc}]} with lsb the field's lowest bit in the packed struct."""
    table = spec["streams"]
    env = base_constants(spec, fp_op_bits)
    constants = []
    for key, entry in table.get("constants", {}).items():
        where = f"{WHERE}: [constants] {key}"
        name = camel(key)
        if not IDENT.match(key) or not isinstance(entry, dict) or set(entry) != {"value", "doc"}:
            raise StreamError(f"{where}: want {{ value = ..., doc = \"...\" }} under a lower_snake name")
        if name in env:
            raise StreamError(f"{where}: {name} is already a spec constant")
        value = evaluate(entry["value"], env, where)
        if value <= 0:
            raise StreamError(f"{where}: {value} is not positive")
        env[name] = value
        constants.append((name, value, entry["value"], entry["doc"]))
    for c in spec["configs"]["config"]:
        for field, bits in (("shader_cores", "CoreBits"), ("threads_per_core", "ThreadBits")):
            if bits in env and c[field] > 1 << env[bits]:
                raise StreamError(f"{WHERE}: config '{c['name']}' has {field} = {c[field]}, more than "
                                  f"{bits} = {env[bits]} can name")
        if c["traversal_units"] != c["intersection_units"]:
            raise StreamError(f"{WHERE}: config '{c['name']}' has {c['traversal_units']} traversal and "
                              f"{c['intersection_units']} intersection units; the RTL's ray units pair one of each")
        if "CacheTagBits" in env:
            # A ray unit keeps an intersection record's lines in flight under the tag
            # bits its cache arbiter leaves (rtl/rpu_top.sv PortTagBits).
            lines = max(env["TriangleRecordWoopBytes"], env["TriangleRecordWatertightBytes"]) // env["MemLineBytes"]
            pair_units = c["traversal_units"] // c["ray_caches"]
            own = env["CacheTagBits"] - (pair_units - 1).bit_length()
            if own < 1 or 1 << own < lines:
                raise StreamError(f"{WHERE}: config '{c['name']}' has {pair_units} traversal units a cache pair; "
                                  f"CacheTagBits = {env['CacheTagBits']} leaves each {max(own, 0)} tag bits, too few "
                                  f"for an intersection record's {lines} lines in flight")
        if "ChunkLanes" in env and c["chunk_size"] > env["ChunkLanes"]:
            raise StreamError(f"{WHERE}: config '{c['name']}' has chunk_size = {c['chunk_size']}, more than "
                              f"ChunkLanes = {env['ChunkLanes']}")
        for cache in ("node_cache", "triangle_cache", "data_cache"):
            if "DramLineBytes" in env and c[cache]["line_bytes"] != env["DramLineBytes"]:
                raise StreamError(f"{WHERE}: config '{c['name']}' has {cache}.line_bytes = "
                                  f"{c[cache]['line_bytes']}; the memory port moves DramLineBytes = "
                                  f"{env['DramLineBytes']}")
            # A line read's tag at the memory port: the cache above DramMshrBits, its
            # miss register below (rtl/rpu_cache.sv, rtl/rpu_mem_arbiter.sv).
            if "DramMshrBits" in env and c[cache]["mshrs"] > 1 << env["DramMshrBits"]:
                raise StreamError(f"{WHERE}: config '{c['name']}' has {cache}.mshrs = {c[cache]['mshrs']}, more "
                                  f"than DramMshrBits = {env['DramMshrBits']} can name")
        if {"DramMshrBits", "DramTagBits"} <= env.keys():
            caches = 2 * c["ray_caches"] + c["shader_cores"]  # node and triangle pairs, a data cache per core
            if env["DramMshrBits"] >= env["DramTagBits"] or caches > 1 << (env["DramTagBits"] - env["DramMshrBits"]):
                raise StreamError(f"{WHERE}: config '{c['name']}' has {caches} caches ({c['ray_caches']} node and "
                                  f"triangle pairs and "
                                  f"{c['shader_cores']} data caches); DramTagBits - DramMshrBits = "
                                  f"{env['DramTagBits'] - env['DramMshrBits']} bits cannot name them")
    faults = len(spec["isa"].get("fault", []))
    if "FaultKindBits" in env and faults > 1 << env["FaultKindBits"]:
        raise StreamError(f"{WHERE}: FaultKindBits = {env['FaultKindBits']} cannot name the {faults} faults of "
                          "spec/isa.toml")
    streams = []
    for name, s in table.get("stream", {}).items():
        where = f"{WHERE}: [stream.{name}]"
        if not IDENT.match(name) or set(s) != {"doc", "fields"} or not s["fields"]:
            raise StreamError(f"{where}: want a lower_snake name, a doc and at least one field")
        fields, seen = [], set()
        for f in s["fields"]:
            here = f"{where} field '{f.get('name', '?')}'"
            if not IDENT.match(f.get("name", "")) or f["name"] in seen:
                raise StreamError(f"{here}: missing, malformed or duplicate name")
            seen.add(f["name"])
            extra = set(f) - {"name", "width", "count", "doc", "sv_type"}
            if extra or "width" not in f or "doc" not in f:
                raise StreamError(f"{here}: needs name, width and doc (and may have count, sv_type), "
                                  f"not {sorted(extra)}")
            width = evaluate(f["width"], env, here)
            count = evaluate(f["count"], env, here) if "count" in f else None
            if count is not None and (width != 32 or count < 1):
                raise StreamError(f"{here}: a vector (count) is of 32-bit words")
            if not 1 <= width <= 32:
                raise StreamError(f"{here}: width {width} is not in 1..32; wider fields are vectors of "
                                  "32-bit words (count)")
            fields.append({"name": f["name"], "width": width, "count": count, "doc": f["doc"],
                           "bits": width * (count or 1), "sv_type": f.get("sv_type"),
                           "width_src": f["width"], "count_src": f.get("count")})
        lsb = 0
        for f in reversed(fields):
            f["lsb"] = lsb
            lsb += f["bits"]
        streams.append({"name": name, "doc": s["doc"], "bits": lsb, "fields": fields})
    return {"constants": constants, "streams": streams}


def validate(spec: dict, fp_op_bits: int) -> None:
    layout(spec, fp_op_bits)


def _sv_width(src, value: int) -> str:
    # A plain constant name reads better than its value; an expression is written out.
    return src if isinstance(src, str) and src.isidentifier() else str(value)


def gen_sv(spec: dict, fp_op_bits: int) -> list[str]:
    """rpu_pkg's stream constants, structs and <Stream>Bits (Yosys 0.23 reads no
    $bits(type), so the width is a number)."""
    lay = layout(spec, fp_op_bits)
    out = ["", "  // Streams (spec/streams.toml, docs/streams.md)."]
    for name, value, src, doc in lay["constants"]:
        note = "" if isinstance(src, int) else f" = {src}"
        out.append(f"  localparam int unsigned {name} = {value};  // {doc}{note}")
    for s in lay["streams"]:
        out += ["", f"  // {s['doc']}", "  typedef struct packed {"]
        for f in s["fields"]:
            if f["sv_type"]:
                decl = f["sv_type"]
            elif f["count"] is not None:
                decl = f"logic [{_sv_width(f['count_src'], f['count'])}*32-1:0]"
            elif f["width"] == 1:
                decl = "logic"
            elif isinstance(f["width_src"], str) and f["width_src"].isidentifier():
                decl = f"logic [{f['width_src']}-1:0]"
            else:
                decl = f"logic [{f['width'] - 1}:0]"
            out.append(f"    {decl} {f['name']};  // {f['doc']}")
        out += [f"  }} {s['name']}_t;", f"  localparam int unsigned {camel(s['name'])}Bits = {s['bits']};"]
    return out


def _cpp_string(s: str) -> str:
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def gen_cpp(spec: dict, fp_op_bits: int, banner: str) -> str:
    """rpu/streams.hpp: the constants, and per stream a struct with kBits, pack() to and
    unpack() from words in the SV bit order, and fields() naming each field's words."""
    lay = layout(spec, fp_op_bits)
    out = [f"// {banner}", "#pragma once", "", "#include <array>", "#include <cstddef>", "#include <cstdint>",
           "#include <string_view>", "#include <tuple>", "", "// The streams between units and between C++ and RTL (spec/streams.toml,",
           "// docs/streams.md). A stream packs into 32-bit words as the SV packed struct",
           "// does: the first field is the most significant, bit k in bit k % 32 of word k / 32.",
           "namespace rpu::streams {", ""]
    for name, value, src, doc in lay["constants"]:
        note = "" if isinstance(src, int) else f" = {src}"
        out.append(f"inline constexpr std::uint32_t k{name} = {value};  // {doc}{note}")
    out += ["", "// One field of a stream value, for reports: `count` words of `bits` bits each.",
            "struct FieldView {", "  std::string_view name;", "  int bits;", "  int count;",
            "  const std::uint32_t* words;", "};", "",
            "// Where a field sits in the packed struct.", "struct FieldLayout {", "  std::string_view name;",
            "  int lsb;  // of word 0", "  int bits;  // per word", "  int count;", "};", "",
            "namespace detail {", "",
            "// The low `width` bits of `value` into stream bits [lsb, lsb + width) of zeroed words.",
            "template <std::size_t N>",
            "constexpr void put(std::array<std::uint32_t, N>& w, int lsb, int width, std::uint32_t value) {",
            "  const std::uint64_t v = value & (width == 32 ? ~std::uint32_t{0} : (std::uint32_t{1} << width) - 1);",
            "  const int word = lsb / 32, shift = lsb % 32;",
            "  w[word] |= static_cast<std::uint32_t>(v << shift);",
            "  if (shift + width > 32) w[word + 1] |= static_cast<std::uint32_t>(v >> (32 - shift));",
            "}", "",
            "template <std::size_t N>",
            "constexpr std::uint32_t get(const std::array<std::uint32_t, N>& w, int lsb, int width) {",
            "  const int word = lsb / 32, shift = lsb % 32;",
            "  std::uint64_t v = w[word] >> shift;",
            "  if (shift + width > 32) v |= std::uint64_t{w[word + 1]} << (32 - shift);",
            "  return static_cast<std::uint32_t>(v) & (width == 32 ? ~std::uint32_t{0} : (std::uint32_t{1} << width) - 1);",
            "}", "", "}  // namespace detail", ""]
    for s in lay["streams"]:
        cls = camel(s["name"])
        fields = s["fields"]
        words = (s["bits"] + 31) // 32
        out += [f"// {s['doc']}", f"struct {cls} {{",
                f"  static constexpr std::string_view kName = {_cpp_string(s['name'])};",
                f"  static constexpr int kBits = {s['bits']};", f"  static constexpr int kWords = {words};",
                "  using Words = std::array<std::uint32_t, kWords>;",
                f"  static constexpr std::array<FieldLayout, {len(fields)}> kLayout{{{{"]
        out += [f"      {{{_cpp_string(f['name'])}, {f['lsb']}, {f['width']}, {f['count'] or 1}}}," for f in fields]
        out += ["  }};", ""]
        for f in fields:
            if f["count"] is None:
                out.append(f"  std::uint32_t {f['name']} = 0;  // {f['width']} bits: {f['doc']}")
            else:
                out.append(f"  std::array<std::uint32_t, {f['count']}> {f['name']}{{}};  // {f['doc']}")
        out += ["", "  constexpr Words pack() const {", "    Words w{};"]
        for f in fields:
            if f["count"] is None:
                out.append(f"    detail::put(w, {f['lsb']}, {f['width']}, {f['name']});")
            else:
                out.append(f"    for (int k = 0; k < {f['count']}; ++k) detail::put(w, {f['lsb']} + 32 * k, 32, "
                           f"{f['name']}[static_cast<std::size_t>(k)]);")
        out += ["    return w;", "  }", "", f"  static constexpr {cls} unpack(const Words& w) {{", f"    {cls} s;"]
        for f in fields:
            if f["count"] is None:
                out.append(f"    s.{f['name']} = detail::get(w, {f['lsb']}, {f['width']});")
            else:
                out.append(f"    for (int k = 0; k < {f['count']}; ++k) s.{f['name']}[static_cast<std::size_t>(k)] "
                           f"= detail::get(w, {f['lsb']} + 32 * k, 32);")
        out += ["    return s;", "  }", "",
                f"  std::array<FieldView, {len(fields)}> fields() const {{", "    return {{"]
        for f in fields:
            ptr = f"&{f['name']}" if f["count"] is None else f"{f['name']}.data()"
            out.append(f"        {{{_cpp_string(f['name'])}, {f['width']}, {f['count'] or 1}, {ptr}}},")
        out += ["    }};", "  }", "", f"  bool operator==(const {cls}&) const = default;", "};", ""]
    names = ", ".join(camel(s["name"]) for s in lay["streams"])
    out += ["// Every stream, for code that walks them all (tests, reports).", f"using All = std::tuple<{names}>;", "",
            "}  // namespace rpu::streams", ""]
    return "\n".join(out)


def gen_doc(spec: dict, fp_op_bits: int, banner: str) -> str:
    """docs/streams.md: the constants and one table per stream, most significant first."""
    lay = layout(spec, fp_op_bits)
    out = [f"<!-- {banner} -->", "# Streams", "",
           "Every struct that crosses between units or between C++ and the RTL, generated from "
           "[`spec/streams.toml`](../spec/streams.toml), which also generates the packed structs "
           "`<stream>_t` and their widths `<Stream>Bits` in `rpu_pkg.sv` and the C++ structs of "
           "`rpu/streams.hpp` (`rpu::streams`, with `pack()`/`unpack()` to 32-bit words). The first "
           "field is the most significant; a vector's word k sits at bits [32k +: 32] of the field. "
           "How the harnesses and the Verilated tops use them: [rtl.md](rtl.md#streams).", "",
           "## Constants", "", "| name | value | from | meaning |", "|---|--:|---|---|"]
    for name, value, src, doc in lay["constants"]:
        out.append(f"| `{name}` | {value} | {'' if isinstance(src, int) else f'`{src}`'} | {doc} |")
    for s in lay["streams"]:
        out += ["", f"## {s['name']}", "", f"{s['doc']} {s['bits']} bits (`{camel(s['name'])}Bits`).", "",
                "| field | bits | width | meaning |", "|---|---|---|---|"]
        for f in s["fields"]:
            hi = f["lsb"] + f["bits"] - 1
            src = f["width_src"] if f["count"] is None else f"{f['count_src']} x 32"
            width = f"{f['bits']}" + ("" if isinstance(src, int) or str(src) == str(f["bits"]) else f" (`{src}`)")
            out.append(f"| {f['name']} | {hi}:{f['lsb']} | {width} | {f['doc'].replace('|', '&#124;')} |")
    out.append("")
    return "\n".join(out)
