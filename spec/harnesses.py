"""The co-simulation harnesses of spec/harnesses.toml: each unit's ports read from its
SystemVerilog header, and from them the Verilated top, the C++ port structs and their
binding to a Verilated top (gen.py --harness-dir; rtl/flow.py for synthesis; docs/rtl.md
"Harnesses").

The headers are read, not parsed in general: the RTL declares its modules in one style
(docs/style.md "SystemVerilog"): `module name #(parameter int unsigned P = expr, ...,
localparam int unsigned L = expr) (input|output <type> [range] name_i|_o, ...);` with a
type of `logic` or `rpu_pkg::<stream>_t`. Anything else is an error naming the line.
"""
from __future__ import annotations

import dataclasses
import pathlib
import re

import streams
from names import camel

WHERE = "spec/harnesses.toml"
HARNESS_KEYS = {"doc", "module", "choose", "params", "set", "rename", "tie", "drop", "on_demand", "arrays"}


class HarnessError(Exception):
    pass


@dataclasses.dataclass
class Param:
    name: str
    default: str
    local: bool


@dataclasses.dataclass
class Port:
    direction: str   # "input" or "output"
    name: str        # with its _i/_o suffix
    sv_type: str     # "logic" or "rpu_pkg::x_t"
    width: str       # the range's upper bound + 1 as written ("" for one bit), e.g. "CodeAddrBits"
    stream: str = ""     # a stream's name: the port is one (sv_type) or `count` side by side
    count: str = ""      # how many streams side by side ("" for one)
    bit_array: str = ""  # a [N-1:0] port whose N counts streams of the module: one bool each

    @property
    def field(self) -> str:
        """The C++ member: the port's name without its direction suffix."""
        return re.sub(r"_n?[io]$", lambda m: "_n" if m.group(0).startswith("_n") else "", self.name)


@dataclasses.dataclass
class Module:
    name: str
    path: pathlib.Path
    params: list[Param]
    ports: list[Port]


HEADER = re.compile(r"^module\s+(\w+)\s*#\s*\((.*?)^\)\s*\((.*?)^\);", re.S | re.M)
PARAM = re.compile(r"^(parameter|localparam)\s+int\s+unsigned\s+(\w+)\s*=\s*(.+)$")
PORT = re.compile(r"^(input|output)\s+(logic|rpu_pkg::\w+_t)\s*(?:\[\s*(.+?)\s*:\s*0\s*\])?\s*(\w+)$")
ARRAY = re.compile(r"^(.+?)\s*\*\s*rpu_pkg::(\w+)Bits$")
ONE = re.compile(r"^rpu_pkg::(\w+)Bits$")


def _items(text: str) -> list[str]:
    """The comma-separated items of a header list, comments and blank lines removed."""
    text = re.sub(r"//[^\n]*", "", text)
    return [" ".join(item.split()) for item in text.split(",") if item.strip()]


def read_module(name: str, search: list[pathlib.Path], stream_names: set[str]) -> Module:
    """The header of `module name` from the first <dir>/<name>.sv of `search`."""
    for d in search:
        path = d / f"{name}.sv"
        if path.is_file():
            break
    else:
        raise HarnessError(f"{WHERE}: no {name}.sv in {', '.join(str(d) for d in search)}")
    text = path.read_text()
    m = HEADER.search(text)
    if not m or m.group(1) != name:
        raise HarnessError(f"{path}: no ANSI header 'module {name} #(...) (...);' (docs/style.md)")
    line = text[:m.start()].count("\n") + 1
    params = []
    for item in _items(m.group(2)):
        p = PARAM.match(item)
        if not p:
            raise HarnessError(f"{path}:{line}: parameter '{item}' is not 'parameter int unsigned Name = value'")
        params.append(Param(p.group(2), p.group(3), p.group(1) == "localparam"))
    by_bits = {camel(s): s for s in stream_names}
    ports = []
    for item in _items(m.group(3)):
        p = PORT.match(item)
        if not p:
            raise HarnessError(f"{path}:{line}: port '{item}' is not 'input|output logic|rpu_pkg::x_t [W-1:0] name'")
        direction, sv_type, msb, port_name = p.groups()
        # [W-1:0] is W bits, [N:0] N + 1.
        width = msb[:-2].strip() if msb and msb.replace(" ", "").endswith("-1") else str(int(msb) + 1) if msb else ""
        if not re.search(r"_n?[io]$", port_name) or (direction == "input") != port_name.endswith(("_i", "_ni")):
            raise HarnessError(f"{path}:{line}: port {port_name}: an input ends in _i, an output in _o")
        port = Port(direction, port_name, sv_type, width or "")
        if sv_type != "logic":
            port.stream = sv_type[len("rpu_pkg::"):-len("_t")]
            if port.stream not in stream_names or width:
                raise HarnessError(f"{path}:{line}: port {port_name}: {sv_type} is not a stream of spec/streams.toml")
        elif width and (a := ARRAY.match(width)) and a.group(2) in by_bits:
            port.stream, port.count = by_bits[a.group(2)], a.group(1).strip("() ")
        elif width and (s := ONE.match(width)) and s.group(1) in by_bits:
            port.stream = by_bits[s.group(1)]  # a stream already flat in the module
        ports.append(port)
    counts = {p.count for p in ports if p.count}
    for port in ports:
        if port.sv_type == "logic" and not port.stream and port.width in counts:
            port.bit_array = port.width
    return Module(name, path, params, ports)


@dataclasses.dataclass
class Harness:
    name: str
    doc: str
    top: str
    modules: list[tuple[Module, str]]  # (module, when); the last has when ""
    params: list[tuple[str, str, str]]  # the top's (name, default, doc), module parameters renamed
    localparams: list[tuple[str, str]]
    set: dict[str, str]
    rename: dict[str, str]
    tie: dict[str, str]
    drop: list[str]
    on_demand: list[str]
    ports: list[Port]                   # the top's, in the first module's order
    array_max: dict[str, int]           # the largest count of each array port's count expression

    @property
    def cpp(self) -> str:
        return camel(self.name)


def _count_value(expr: str, env: dict[str, int], where: str) -> int:
    return streams.evaluate(expr, env, where)


def load(spec: dict, fp_op_bits: int, search: list[pathlib.Path]) -> list[Harness]:
    """Every harness of spec["harnesses"], its modules read from `search` (rtl/, sim/)."""
    try:
        return _load(spec, fp_op_bits, search)
    except streams.StreamError as e:
        raise HarnessError(str(e)) from e


def _load(spec: dict, fp_op_bits: int, search: list[pathlib.Path]) -> list[Harness]:
    lay = streams.layout(spec, fp_op_bits)
    stream_names = {s["name"] for s in lay["streams"]}
    env = streams.base_constants(spec, fp_op_bits)
    env.update({name: value for name, value, _, _ in lay["constants"]})
    out = []
    for name, h in spec["harnesses"].get("harness", {}).items():
        where = f"{WHERE}: [harness.{name}]"
        if not streams.IDENT.match(name) or set(h) - HARNESS_KEYS or ("module" in h) == ("choose" in h):
            raise HarnessError(f"{where}: a lower_snake name with a doc and one of module or choose "
                               f"(and of {sorted(HARNESS_KEYS)})")
        choices = [{"module": h["module"]}] if "module" in h else h["choose"]
        if any("when" not in c for c in choices[:-1]) or "when" in choices[-1]:
            raise HarnessError(f"{where}: every choice but the last has a `when`")
        modules = [(read_module(c["module"], search, stream_names), c.get("when", "")) for c in choices]
        rename, setp = h.get("rename", {}), h.get("set", {})
        tie, drop, on_demand = h.get("tie", {}), h.get("drop", []), h.get("on_demand", [])
        params, localparams, seen = [], [], set()
        for p in h.get("params", []):
            params.append((p["name"], str(p["default"]), p.get("doc", "")))
            seen.add(p["name"])
        ports, port_names = [], {}
        for module, _ in modules:
            for p in module.params:
                top_name = rename.get(p.name, p.name)
                if p.name in setp or top_name in seen:
                    continue
                seen.add(top_name)
                (localparams.append((top_name, p.default)) if p.local else params.append((top_name, p.default, "")))
            for p in module.ports:
                if p.name in tie or p.name in drop or p.name in ("clk_i",):
                    continue
                if p.name in port_names:
                    q = port_names[p.name]
                    if (q.direction, q.sv_type, q.width) != (p.direction, p.sv_type, p.width):
                        raise HarnessError(f"{where}: port {p.name} differs between {modules[0][0].name} and "
                                           f"{module.name}")
                    continue
                port_names[p.name] = p
                ports.append(p)
        for port in list(tie) + drop + on_demand:
            if not any(port == p.name for m, _ in modules for p in m.ports):
                raise HarnessError(f"{where}: no module of it has a port {port}")
        if [p.name for p in ports[:1]] != ["rst_ni"]:
            raise HarnessError(f"{where}: the module's first ports are clk_i and rst_ni")
        # The count expressions' largest values: array parameters at their maxima, the
        # module's localparams at their values.
        count_env = dict(env)
        for pname, expr in h.get("arrays", {}).items():
            count_env[pname] = streams.evaluate(expr, env, f"{where} arrays.{pname}")
        local_env = dict(count_env)
        for pname, default in localparams:
            try:
                local_env[pname] = _count_value(default.replace("rpu_pkg::", ""), local_env, where)
            except streams.StreamError:
                pass  # a localparam of a parameter the top may set ($clog2(CodeWords)): never a count
        array_max = {}
        for p in ports:
            if p.count or p.bit_array:
                expr = p.count or p.bit_array
                try:
                    array_max[expr] = _count_value(expr, local_env, f"{where} port {p.name}")
                except streams.StreamError as e:
                    raise HarnessError(f"{e}: a count of side-by-side streams is an `arrays` parameter or "
                                       "a localparam") from e
        out.append(Harness(name, h["doc"], f"rpu_{name}_cosim_top", modules, params, localparams, setp, rename, tie,
                           drop, on_demand, ports, array_max))
    return out


# ---------------------------------------------------------------------------------------
# The top.

def _flat(p: Port) -> str:
    """The port's declaration in the top: a stream as a flat vector of its width."""
    if p.sv_type != "logic":
        return f"logic [rpu_pkg::{camel(p.stream)}Bits-1:0]"
    return f"logic [{p.width}-1:0]" if p.width else "logic"


def gen_top(h: Harness, banner: str) -> str:
    out = [f"// {banner}", f"// {h.doc}", "// Each stream one flat port of its rpu_pkg width (spec/streams.toml). Only wiring:",
           "// a synthesis of this top has the unit's cells.", f"module {h.top} #("]
    decls = [f"  parameter int unsigned {n} = {d}" for n, d, _ in h.params]
    decls += [f"  localparam int unsigned {n} = {d}" for n, d in h.localparams]
    out.append(",\n".join(decls))
    out.append(") (")
    ports = ["  input  logic clk_i"] + [f"  {p.direction:<6} {_flat(p)} {p.name}" for p in h.ports]
    out.append(",\n".join(ports))
    out += [");", ""]
    streamed = [p for p in h.ports if p.sv_type != "logic"]
    for p in streamed:
        out.append(f"  {p.sv_type} {p.field};")
    for p in streamed:
        out.append(f"  assign {p.field} = {p.name};" if p.direction == "input" else f"  assign {p.name} = {p.field};")
    out.append("")
    for k, (module, when) in enumerate(h.modules):
        indent = "  "
        if len(h.modules) > 1:
            head = "if" if k == 0 else "end else if" if when else "end else"
            out.append(f"  {head}{f' ({when})' if when else ''} begin : g_{module.name[len('rpu_'):]}")
            indent = "    "
        own = {p.name for p in module.ports}
        params = [f".{p.name}({h.set.get(p.name, h.rename.get(p.name, p.name))})" for p in module.params
                  if not p.local]
        conns = []
        dropped = []
        for p in module.ports:
            if p.name == "clk_i":
                conns.append(".clk_i")
            elif p.name in h.tie:
                conns.append(f".{p.name}({h.tie[p.name]})")
            elif p.name in h.drop:
                out.append(f"{indent}{p.sv_type if p.sv_type != 'logic' else _flat(p)} {p.field}_dropped;")
                conns.append(f".{p.name}({p.field}_dropped)")
                dropped.append(f"{p.field}_dropped")
            elif p.sv_type != "logic":
                conns.append(f".{p.name}({p.field})")
            else:
                conns.append(f".{p.name}")
        out.append(f"{indent}{module.name} #({', '.join(params)}) u_{module.name[len('rpu_'):]} (")
        out.append(",\n".join(f"{indent}  {c}" for c in conns))
        out.append(f"{indent});")
        # The top's ports this module lacks: outputs held at zero, inputs read by nothing.
        absent = [p for p in h.ports if p.name not in own]
        for p in absent:
            if p.direction == "output":
                out.append(f"{indent}assign {p.field if p.sv_type != 'logic' else p.name} = '0;")
        unused = dropped + [p.field if p.sv_type != "logic" else p.name for p in absent
                            if p.direction == "input"]
        if unused:
            out.append(f"{indent}logic unused_{module.name[len('rpu_'):]};")
            out.append(f"{indent}assign unused_{module.name[len('rpu_'):]} = ^{{{', '.join(unused)}}};")
    if len(h.modules) > 1:
        out.append("  end")
    out += ["", "endmodule", ""]
    return "\n".join(out)


# ---------------------------------------------------------------------------------------
# The C++ side.

def _cpp_type(h: Harness, p: Port) -> str:
    if p.stream and p.count:
        return f"std::array<streams::{camel(p.stream)}, {h.array_max[p.count]}>"
    if p.stream:
        return f"streams::{camel(p.stream)}"
    if p.bit_array:
        return f"std::array<bool, {h.array_max[p.bit_array]}>"
    return "bool" if not p.width else "std::uint64_t"


def gen_ports_hpp(h: Harness, banner: str) -> str:
    """rpu/harness/<name>.hpp: what a harness sets and reads, without Verilator."""
    out = [f"// {banner}", "#pragma once", "", "#include <array>", "#include <cstdint>", "",
           '#include "rpu/streams.hpp"', "", f"// {h.doc}",
           f"// The ports of {h.top} ({', '.join(str(m.path.name) for m, _ in h.modules)}), as C++: a stream as its",
           "// rpu::streams struct, side-by-side streams as an array, a bit as bool, a vector as an integer.",
           "namespace rpu::sim::harness {", "", f"struct {h.cpp} {{",
           f'  static constexpr const char* kTop = "{h.top}";', "", "  struct Inputs {"]
    for p in h.ports:
        if p.direction == "input":
            out.append(f"    {_cpp_type(h, p)} {p.field}{{}};")
    out += ["  };", "", "  // Read at every settle() but the on-demand ones (Model::read_on_demand).", "  struct Outputs {"]
    for p in h.ports:
        if p.direction == "output":
            note = "  // on demand" if p.name in h.on_demand else ""
            out.append(f"    {_cpp_type(h, p)} {p.field}{{}};{note}")
    out += ["  };", "};", "", "}  // namespace rpu::sim::harness", ""]
    return "\n".join(out)


def _valid_of(h: Harness, p: Port) -> Port | None:
    """A stream output's valid: <x>_valid_o beside <x>_o."""
    name = p.name[:-len("_o")] + "_valid_o"
    return next((q for q in h.ports if q.name == name), None)


def gen_binding_hpp(h: Harness, banner: str) -> str:
    """rpu/harness/<name>_binding.hpp: Inputs and Outputs to and from a Verilated top."""
    c = h.cpp
    out = [f"// {banner}", "#pragma once", "", '#include "port_vectors.hpp"', '#include "verilated_dut.hpp"',
           f'#include "rpu/harness/{h.name}.hpp"', "", "namespace rpu::sim {", "",
           f"template <> struct Binding<harness::{c}> {{", "  template <class Top>",
           f"  static void write(Top& t, const harness::{c}::Inputs& in) {{"]
    for p in h.ports:
        if p.direction != "input":
            continue
        if p.stream and p.count:
            out += _each_stream(p, "in", f"to_port_at(t.{p.name}, k, in.{p.field}[k]);")
        elif p.stream:
            out.append(f"    to_port(t.{p.name}, in.{p.field}.pack());")
        elif p.bit_array:
            out.append(f"    set_bits(t.{p.name}, in.{p.field});")
        else:
            out.append(f"    set_port(t.{p.name}, in.{p.field});")
    out += ["  }", "", "  template <class Top>", f"  static void read(const Top& t, harness::{c}::Outputs& out) {{"]
    out += _reads(h, [p for p in h.ports if p.direction == "output" and p.name not in h.on_demand])
    out += ["  }", "", "  template <class Top>",
            f"  static void read_on_demand(const Top& t, harness::{c}::Outputs& out) {{"]
    on_demand = [p for p in h.ports if p.name in h.on_demand]
    out += _reads(h, on_demand) if on_demand else ["    (void)t;", "    (void)out;"]
    out += ["  }", "", "  // Every port's words in port order (the netlist testbenches' vectors).", "  template <class Top>",
            "  static PortWords words(const Top& t) {", "    PortWords w;"]
    for p in h.ports:
        out.append(f"    append_words(w.{'inputs' if p.direction == 'input' else 'outputs'}, t.{p.name});")
    out += ["    return w;", "  }", "};", "", "}  // namespace rpu::sim", ""]
    return "\n".join(out)


def _each_stream(p: Port, side: str, body: str) -> list[str]:
    """A loop over the streams side by side in port p, as many as both the C++ array
    (`side`.field) and this model's port hold."""
    return [f"    for (std::size_t k = 0; k < {side}.{p.field}.size() && k < port_streams<streams::"
            f"{camel(p.stream)}>(t.{p.name}); ++k) {{", f"      {body}", "    }"]


def _reads(h: Harness, ports: list[Port]) -> list[str]:
    out = []
    for p in ports:
        if p.stream and p.count:
            valid = _valid_of(h, p)
            # Side-by-side records are unpacked only where valid: every core's every
            # cycle would cost more than the model.
            guard = f"if (out.{valid.field}[k]) " if valid is not None and valid.bit_array else ""
            out += _each_stream(p, "out", f"{guard}out.{p.field}[k] = from_port_at<streams::{camel(p.stream)}>("
                                          f"t.{p.name}, k);")
        elif p.stream:
            out.append(f"    out.{p.field} = from_port<streams::{camel(p.stream)}>(t.{p.name});")
        elif p.bit_array:
            out.append(f"    get_bits(t.{p.name}, out.{p.field});")
        elif p.width:
            out.append(f"    out.{p.field} = port_value(t.{p.name});")
        else:
            out.append(f"    out.{p.field} = t.{p.name} != 0;")
    return out


def write_all(harnesses: list[Harness], out_dir: pathlib.Path, banner: str, write) -> None:
    """The tops into out_dir/sim, the headers into out_dir/include/rpu/harness."""
    for h in harnesses:
        write(out_dir / "sim" / f"{h.top}.sv", gen_top(h, banner))
        write(out_dir / "include" / "rpu" / "harness" / f"{h.name}.hpp", gen_ports_hpp(h, banner))
        write(out_dir / "include" / "rpu" / "harness" / f"{h.name}_binding.hpp", gen_binding_hpp(h, banner))
