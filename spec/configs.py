"""Hardware configurations: the key schema (config_keys.toml), the named configurations
(configs.toml) and the measured latencies (latencies.toml), checked and resolved here
and turned into C++ and SystemVerilog by gen.py.

Expressions of derived values and rules are Python expressions over dotted key names,
restricted to integers, + - * // %, comparisons, and/or/not and the functions log2 and
is_pow2. They are evaluated here for the named configurations and translated to C++
for the run-time ones (rpu::config), so one text defines both.
"""
from __future__ import annotations

import ast
import difflib
import re

import doc_blocks
from names import camel

# The groups whose values are measured on the RTL (latencies.toml), with their C++ structs.
LATENCY_GROUPS = {
    "latency": ("LatencyConfig", ("fpu", "sfu", "rsq", "reissue", "result", "to_unit", "from_unit", "from_rays", "line_wait")),
    "tu": ("TraversalUnitConfig", ("setup_woop", "setup_watertight", "inner", "leaf", "pop", "memory_wait", "iu_wait", "turnaround",
                                  "pipe_handoff_woop", "pipe_handoff_watertight", "pipe_node", "pipe_iu_wait",
                                  "pipe_memory_wait", "pipe_memory_wait_by_tag", "pipe_from_unit")),
    "iu": ("IntersectionUnitConfig", ("woop", "watertight", "interval_woop", "interval_watertight")),
}
# The widest fraction a format may have (spec/formats.toml's limit, rpu::fp::soft's).
MAX_FRACTION_BITS = 23
# The C++ table of each latency group's measured entries.
LATENCY_TABLES = {"latency": "kShaderLatencies", "tu": "kTuLatencies", "iu": "kIuLatencies"}
KINDS = ("int", "format")


class ConfigError(Exception):
    pass


def _expand(name: str, templates: dict) -> list[tuple[str, dict]]:
    """`{cache}.bytes` -> [("node_cache.bytes", {"cache": "node_cache"}), ...]."""
    found = re.findall(r"\{([a-z_]+)\}", name)
    if not found:
        return [(name, {})]
    if len(set(found)) != 1 or found[0] not in templates:
        raise ConfigError(f"spec/config_keys.toml: '{name}' uses an unknown or a second template")
    t = found[0]
    return [(name.replace("{" + t + "}", v), {t: v}) for v in templates[t]]


def _subst(text: str, binding: dict) -> str:
    for t, v in binding.items():
        text = text.replace("{" + t + "}", v)
    return text


class Expr:
    """One expression of config_keys.toml, parsed once."""

    ALLOWED_BINOPS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.FloorDiv: "/", ast.Mod: "%"}
    ALLOWED_CMP = {ast.Eq: "==", ast.NotEq: "!=", ast.Lt: "<", ast.LtE: "<=", ast.Gt: ">", ast.GtE: ">="}
    FUNCTIONS = ("log2", "is_pow2")

    def __init__(self, text: str, where: str):
        self.text = text
        self.where = where
        try:
            self.tree = ast.parse(text, mode="eval").body
        except SyntaxError as e:
            raise ConfigError(f"{where}: '{text}' is not an expression: {e.msg}") from e
        self.names: list[str] = []
        self._check(self.tree)

    def _dotted(self, node) -> str | None:
        if isinstance(node, ast.Name):
            return node.id
        if isinstance(node, ast.Attribute):
            head = self._dotted(node.value)
            return None if head is None else f"{head}.{node.attr}"
        return None

    def _check(self, node) -> None:
        name = self._dotted(node)
        if name is not None:
            if name not in self.names:
                self.names.append(name)
        elif isinstance(node, ast.Constant) and type(node.value) is int:
            pass
        elif isinstance(node, ast.BinOp) and type(node.op) in self.ALLOWED_BINOPS:
            self._check(node.left)
            self._check(node.right)
        elif isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.Not, ast.USub)):
            self._check(node.operand)
        elif isinstance(node, ast.BoolOp):
            for v in node.values:
                self._check(v)
        elif isinstance(node, ast.Compare) and all(type(o) in self.ALLOWED_CMP for o in node.ops):
            self._check(node.left)
            for c in node.comparators:
                self._check(c)
        elif (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in self.FUNCTIONS
              and len(node.args) == 1 and not node.keywords):
            self._check(node.args[0])
        else:
            raise ConfigError(f"{self.where}: '{self.text}': '{ast.unparse(node)}' is not allowed "
                              "(integers, names, + - * // %, comparisons, and/or/not, log2, is_pow2)")

    def evaluate(self, env: dict) -> int:
        def ev(node):
            name = self._dotted(node)
            if name is not None:
                return env[name]
            if isinstance(node, ast.Constant):
                return node.value
            if isinstance(node, ast.BinOp):
                a, b = ev(node.left), ev(node.right)
                if isinstance(node.op, ast.Add):
                    return a + b
                if isinstance(node.op, ast.Sub):
                    return a - b
                if isinstance(node.op, ast.Mult):
                    return a * b
                if b == 0:
                    raise ConfigError(f"{self.where}: '{self.text}' divides by zero")
                return a // b if isinstance(node.op, ast.FloorDiv) else a % b
            if isinstance(node, ast.UnaryOp):
                return (not ev(node.operand)) if isinstance(node.op, ast.Not) else -ev(node.operand)
            if isinstance(node, ast.BoolOp):
                values = [bool(ev(v)) for v in node.values]
                return all(values) if isinstance(node.op, ast.And) else any(values)
            if isinstance(node, ast.Compare):
                left = ev(node.left)
                for op, right_node in zip(node.ops, node.comparators):
                    right = ev(right_node)
                    ok = {ast.Eq: left == right, ast.NotEq: left != right, ast.Lt: left < right,
                          ast.LtE: left <= right, ast.Gt: left > right, ast.GtE: left >= right}[type(op)]
                    if not ok:
                        return False
                    left = right
                return True
            x = ev(node.args[0])
            if node.func.id == "log2":
                return max(x, 1).bit_length() - 1
            return x > 0 and x & (x - 1) == 0
        return int(ev(self.tree))

    def cpp(self, value_of) -> str:
        """C++ for the expression; value_of(name) gives the C++ of a name's value."""
        def cc(node) -> str:
            name = self._dotted(node)
            if name is not None:
                return value_of(name)
            if isinstance(node, ast.Constant):
                return f"std::int64_t{{{node.value}}}"
            if isinstance(node, ast.BinOp):
                return f"({cc(node.left)} {self.ALLOWED_BINOPS[type(node.op)]} {cc(node.right)})"
            if isinstance(node, ast.UnaryOp):
                return f"({'!' if isinstance(node.op, ast.Not) else '-'}{cc(node.operand)})"
            if isinstance(node, ast.BoolOp):
                join = " && " if isinstance(node.op, ast.And) else " || "
                return "(" + join.join(cc(v) for v in node.values) + ")"
            if isinstance(node, ast.Compare):
                parts, left = [], cc(node.left)
                for op, right_node in zip(node.ops, node.comparators):
                    right = cc(right_node)
                    parts.append(f"({left} {self.ALLOWED_CMP[type(op)]} {right})")
                    left = right
                return "(" + " && ".join(parts) + ")"
            return f"detail::{node.func.id}({cc(node.args[0])})"
        return cc(self.tree)


class Schema:
    def __init__(self, table: dict, constants: dict):
        self.constants = constants
        templates = table.get("templates", {})
        # A group made from a template ({cache}.x -> node_cache.x) is that template's struct.
        self.group_structs = {v: camel(t) + "Config" for t, values in templates.items() for v in values}
        self.keys: list[dict] = []
        for k in table.get("key", []):
            kind = k.get("kind", "int")
            if kind not in KINDS:
                raise ConfigError(f"spec/config_keys.toml: key '{k.get('name')}': kind must be one of {KINDS}")
            for name, binding in _expand(k["name"], templates):
                entry = {"name": name, "doc": _subst(k["doc"], binding), "kind": kind,
                         "min": k.get("min"), "max": k.get("max"), "pow2": bool(k.get("pow2", False))}
                if kind == "int" and (not isinstance(entry["min"], int) or not isinstance(entry["max"], int)
                                      or entry["min"] > entry["max"]):
                    raise ConfigError(f"spec/config_keys.toml: key '{name}' needs integers min <= max")
                self.keys.append(entry)
        self.derived: list[dict] = []
        for d in table.get("derived", []):
            for name, binding in _expand(d["name"], templates):
                where = f"spec/config_keys.toml: derived '{name}'"
                self.derived.append({"name": name, "doc": _subst(d["doc"], binding),
                                     "expr": Expr(_subst(d["expr"], binding), where)})
        self.rules: list[dict] = []
        for r in table.get("rule", []):
            for _, binding in _expand(r["expr"], templates):
                text = _subst(r["expr"], binding)
                self.rules.append({"expr": Expr(text, f"spec/config_keys.toml: rule '{text}'"),
                                   "message": _subst(r["message"], binding)})
        # A template's instances stay together (node_cache.bytes, node_cache.line_bytes, ...).
        self.keys = _grouped(self.keys)
        self.derived = _grouped(self.derived)
        names = [k["name"] for k in self.keys]
        known = set(names) | set(constants)
        if len(set(names)) != len(names):
            raise ConfigError("spec/config_keys.toml: a key is listed twice")
        for group in LATENCY_GROUPS:
            if any(n.split(".")[0] == group for n in names):
                raise ConfigError(f"spec/config_keys.toml: '{group}' is measured (latencies.toml), not a choice")
        for d in self.derived:
            for n in d["expr"].names:
                if n not in known:
                    raise ConfigError(f"{d['expr'].where}: unknown name '{n}'")
            known.add(d["name"])
        for r in self.rules:
            for n in r["expr"].names:
                if n not in known:
                    raise ConfigError(f"{r['expr'].where}: unknown name '{n}'")

    def groups(self) -> dict[str, list[str]]:
        """Top-level group -> its fields (keys then derived), in order; '' for plain keys."""
        out: dict[str, list[str]] = {}
        for n in [k["name"] for k in self.keys] + [d["name"] for d in self.derived]:
            group, _, field = n.rpartition(".")
            out.setdefault(group, []).append(field)
        return out


def _grouped(entries: list[dict]) -> list[dict]:
    """Stable order by each dotted group's first appearance ('' for plain names)."""
    first: dict[str, int] = {}
    for i, e in enumerate(entries):
        first.setdefault(e["name"].rpartition(".")[0], i)
    return sorted(entries, key=lambda e: first[e["name"].rpartition(".")[0]])


def flatten(config: dict, prefix: str = "") -> dict:
    out = {}
    for k, v in config.items():
        if isinstance(v, dict):
            out.update(flatten(v, f"{prefix}{k}."))
        else:
            out[prefix + k] = v
    return out


def format_fraction_bits(formats: list[dict]) -> dict[str, int]:
    return {f["name"]: f["fraction_bits"] for f in formats}


def measured_entry(table: dict, fraction_bits: int, formats: dict[str, int]) -> str:
    """The latencies.toml entry a format of `fraction_bits` takes (latencies.toml's rule)."""
    wider = sorted((formats[f], f) for f in table if formats[f] >= fraction_bits)
    if wider:
        return wider[0][1]
    return max((formats[f], f) for f in table)[1]


def load_latencies(table: dict, formats: dict[str, int]) -> dict:
    for group, (_, fields) in LATENCY_GROUPS.items():
        entries = table.get(group)
        if not isinstance(entries, dict) or not entries:
            raise ConfigError(f"spec/latencies.toml: [{group}.<format>] tables are missing")
        for fmt, values in entries.items():
            where = f"spec/latencies.toml: [{group}.{fmt}]"
            if fmt not in formats:
                raise ConfigError(f"{where}: unknown format '{fmt}'")
            if set(values) != set(fields):
                raise ConfigError(f"{where}: must have exactly {', '.join(fields)}")
            if any(not isinstance(v, int) or v <= 0 for v in values.values()):
                raise ConfigError(f"{where}: latencies are positive integers")
    if "fp32" not in table["latency"]:
        raise ConfigError("spec/latencies.toml: [latency.fp32] must exist")
    return table


def resolve(config: dict, schema: Schema, latencies: dict, formats: dict[str, int]) -> dict:
    """A named configuration checked against the schema, with its derived values and
    latencies: {"name", "doc", "values": {dotted: int|str}, "latency_format": {group: fmt}}."""
    name = config.get("name", "?")
    where = f"spec/configs.toml: config '{name}'"
    flat = flatten({k: v for k, v in config.items() if k not in ("name", "doc")})
    names = [k["name"] for k in schema.keys]
    for k in flat:
        if k.split(".")[0] in LATENCY_GROUPS:
            raise ConfigError(f"{where}: '{k}' is measured on the RTL (spec/latencies.toml, by the format), "
                              "not a choice")
        if k not in names:
            hint = difflib.get_close_matches(k, names, n=1)
            raise ConfigError(f"{where}: unknown key '{k}'" + (f" (did you mean '{hint[0]}'?)" if hint else ""))
    missing = [k for k in names if k not in flat]
    if missing:
        raise ConfigError(f"{where}: missing {', '.join(missing)}")
    for k in schema.keys:
        v = flat[k["name"]]
        if k["kind"] == "format":
            if v not in formats:
                raise ConfigError(f"{where}: {k['name']} = '{v}' is not a format of spec/formats.toml")
            continue
        if not isinstance(v, int) or isinstance(v, bool) or not k["min"] <= v <= k["max"]:
            raise ConfigError(f"{where}: {k['name']} = {v!r} is not an integer in [{k['min']}, {k['max']}]")
        if k["pow2"] and v & (v - 1):
            raise ConfigError(f"{where}: {k['name']} = {v} is not a power of two")
    env = dict(schema.constants)
    env.update(flat)
    for d in schema.derived:
        env[d["name"]] = d["expr"].evaluate(env)
    for r in schema.rules:
        if not r["expr"].evaluate(env):
            values = ", ".join(f"{n} = {env[n]}" for n in r["expr"].names if n not in schema.constants)
            raise ConfigError(f"{where}: {r['message']} ({values})")
    values = {k: env[k] for k in names + [d["name"] for d in schema.derived]}
    fbits = formats[flat["format"]]
    chosen = {g: measured_entry(latencies[g], fbits, formats) for g in LATENCY_GROUPS}
    for g, (_, fields) in LATENCY_GROUPS.items():
        for f in fields:
            values[f"{g}.{f}"] = latencies[g][chosen[g]][f]
    return {"name": name, "doc": config.get("doc", ""), "values": values, "latency_format": chosen}



def cpp_string(s: str) -> str:
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _cpp_value(schema: Schema, name: str) -> str:
    if name in schema.constants:
        return f"std::int64_t{{{schema.constants[name]}}}"
    return f"std::int64_t{{c.{name}}}"


def gen_cpp(schema: Schema, resolved: list[dict], latencies: dict, formats: dict[str, int]) -> list[str]:
    """The configuration part of rpu/spec.hpp (namespace rpu::spec)."""
    out = ["// Hardware configurations (spec/config_keys.toml, configs.toml, latencies.toml).",
           "namespace detail {",
           "constexpr std::int64_t log2(std::int64_t x) {",
           "  return x < 1 ? 0 : std::bit_width(static_cast<std::uint64_t>(x)) - 1;", "}",
           "constexpr bool is_pow2(std::int64_t x) { return x > 0 && std::has_single_bit(static_cast<std::uint64_t>(x)); }",
           "}  // namespace detail", ""]
    groups = schema.groups()
    for group, (struct, fields) in LATENCY_GROUPS.items():
        out += [f"struct {struct} {{"] + [f"  int {f};" for f in fields] + ["};", ""]
    emitted = set()
    for group, fields in groups.items():
        struct = schema.group_structs.get(group, camel(group) + "Config")
        if not group or struct in emitted:
            continue
        emitted.add(struct)
        out += [f"struct {struct} {{"] + [f"  int {f};" for f in fields] + ["};", ""]
    kinds = {k["name"]: k["kind"] for k in schema.keys}
    out += ["struct HardwareConfig {", "  std::string name;", "  std::string doc;"]
    for field in groups.get("", []):
        out.append(f"  {'std::string' if kinds.get(field) == 'format' else 'int'} {field};")
    for group in groups:
        if group:
            out.append(f"  {schema.group_structs.get(group, camel(group) + 'Config')} {group};")
    for group, (struct, _) in LATENCY_GROUPS.items():
        out.append(f"  {struct} {group};  // spec/latencies.toml")
    out.append("  // The latencies.toml entry each of latency, tu and iu took, by the format.")
    out += [f"  std::string {group}_format;" for group in LATENCY_GROUPS]
    out += ["};", ""]

    def init(r: dict) -> str:
        v = r["values"]
        parts = [f".name = {cpp_string(r['name'])}", f".doc = {cpp_string(r['doc'])}"]
        for field in groups.get("", []):
            parts.append(f".{field} = " + (cpp_string(v[field]) if kinds.get(field) == "format" else str(v[field])))
        for group, fields in groups.items():
            if group:
                parts.append(f".{group} = {{" + ", ".join(f".{f} = {v[group + '.' + f]}" for f in fields) + "}")
        for group, (_, fields) in LATENCY_GROUPS.items():
            parts.append(f".{group} = {{" + ", ".join(f".{f} = {v[group + '.' + f]}" for f in fields) + "}")
        parts += [f".{g}_format = {cpp_string(r['latency_format'][g])}" for g in LATENCY_GROUPS]
        return "    HardwareConfig{" + ",\n                   ".join(parts) + "},"
    out += ["// The named configurations, resolved: derived values and latencies filled in.",
            f"inline const std::array<HardwareConfig, {len(resolved)}> kConfigs{{{{"]
    out += [init(r) for r in resolved]
    out += ["}};", ""]

    out += ["template <class T>", "struct MeasuredLatency {", "  std::string_view format;", "  T value;", "};"]
    for group, (struct, fields) in LATENCY_GROUPS.items():
        entries = latencies[group]
        out.append(f"inline constexpr std::array<MeasuredLatency<{struct}>, {len(entries)}> "
                   f"{LATENCY_TABLES[group]}{{{{")
        for fmt, values in entries.items():
            out.append(f"    {{{cpp_string(fmt)}, {{" + ", ".join(str(values[f]) for f in fields) + "}},")
        out += ["}};"]
    # measured_entry's rule, once: the entry a format of f fraction bits (1..23) takes.
    out.append("// The index into each table above that a format of f fraction bits takes (latencies.toml's rule).")
    for group in LATENCY_GROUPS:
        names = list(latencies[group])
        picks = [0] + [names.index(measured_entry(latencies[group], f, formats)) for f in range(1, MAX_FRACTION_BITS + 1)]
        out.append(f"inline constexpr std::array<std::uint8_t, {len(picks)}> {LATENCY_TABLES[group]}ByFractionBits{{{{"
                   + ", ".join(map(str, picks)) + "}};")
    out.append("")

    out += ["enum class KeyKind : std::uint8_t { kInt, kFormat };", "",
            "// A choice of a configuration (config_keys.toml); get/set are null for kFormat.",
            "struct ConfigKey {", "  std::string_view name;", "  std::string_view doc;", "  KeyKind kind;",
            "  std::int64_t min;", "  std::int64_t max;", "  bool pow2;",
            "  std::int64_t (*get)(const HardwareConfig&);", "  void (*set)(HardwareConfig&, std::int64_t);",
            "};", f"inline constexpr std::array<ConfigKey, {len(schema.keys)}> kConfigKeys{{{{"]
    for k in schema.keys:
        if k["kind"] == "format":
            out.append(f"    {{{cpp_string(k['name'])}, {cpp_string(k['doc'])}, KeyKind::kFormat, 0, 0, false, "
                       "nullptr, nullptr},")
            continue
        n = k["name"]
        out.append(f"    {{{cpp_string(n)}, {cpp_string(k['doc'])}, KeyKind::kInt, {k['min']}, {k['max']}, "
                   f"{'true' if k['pow2'] else 'false'},\n"
                   f"     [](const HardwareConfig& c) -> std::int64_t {{ return c.{n}; }},\n"
                   f"     [](HardwareConfig& c, std::int64_t v) {{ c.{n} = static_cast<int>(v); }}}},")
    out += ["}};", "",
            "// A value that follows from the choices, and the expression it follows by.",
            "struct DerivedValue {", "  std::string_view name;", "  std::string_view doc;",
            "  std::string_view expr;", "  std::int64_t (*get)(const HardwareConfig&);", "};",
            f"inline constexpr std::array<DerivedValue, {len(schema.derived)}> kDerivedValues{{{{"]
    for d in schema.derived:
        out.append(f"    {{{cpp_string(d['name'])}, {cpp_string(d['doc'])}, {cpp_string(d['expr'].text)}, "
                   f"[](const HardwareConfig& c) -> std::int64_t {{ return c.{d['name']}; }}}},")
    out += ["}};", "", "// A latency of spec/latencies.toml as the configuration holds it.",
            "struct MeasuredValue {", "  std::string_view name;", "  std::int64_t (*get)(const HardwareConfig&);", "};"]
    measured = [f"{g}.{f}" for g, (_, fields) in LATENCY_GROUPS.items() for f in fields]
    out.append(f"inline constexpr std::array<MeasuredValue, {len(measured)}> kMeasuredValues{{{{")
    out += [f"    {{{cpp_string(m)}, [](const HardwareConfig& c) -> std::int64_t {{ return c.{m}; }}}},"
            for m in measured]
    out += ["}};", "", "// Sets the derived values from the choices (kConfigKeys' ranges already hold).",
            "inline void derive(HardwareConfig& c) {"]
    for d in schema.derived:
        out.append(f"  c.{d['name']} = static_cast<int>({d['expr'].cpp(lambda n: _cpp_value(schema, n))});")
    out += ["}", "",
            "// A condition every configuration meets; `names` are the values its message shows.",
            "struct ConfigRule {", "  std::string_view expr;", "  std::string_view message;",
            "  std::string_view names;  // space-separated", "  bool (*holds)(const HardwareConfig&);", "};",
            f"inline constexpr std::array<ConfigRule, {len(schema.rules)}> kConfigRules{{{{"]
    for r in schema.rules:
        names = " ".join(n for n in r["expr"].names if n not in schema.constants)
        out.append(f"    {{{cpp_string(r['expr'].text)}, {cpp_string(r['message'])}, {cpp_string(names)},\n"
                   f"     [](const HardwareConfig& c) -> bool {{ return {r['expr'].cpp(lambda n: _cpp_value(schema, n))}; }}}},")
    out += ["}};", ""]
    return out


def gen_sv(resolved: list[dict]) -> list[str]:
    out = []
    for r in resolved:
        n = camel(r["name"])
        for key, value in r["values"].items():
            if isinstance(value, int):
                out.append(f"  localparam int unsigned Config{n}{camel(key)} = {value};")
    return out


def _size(n: int) -> str:
    return f"{n // 1024} KiB" if n % 1024 == 0 and n >= 1024 else f"{n} B"


def doc_tables(schema: Schema, resolved: list[dict]) -> dict[str, str]:
    """The generated blocks of docs/configurations.md: 'keys' and 'named'."""
    keys = ["| key | range | meaning |", "|---|---|---|"]
    for k in schema.keys:
        if k["kind"] == "format":
            keys.append(f"| `{k['name']}` | a format of spec/formats.toml or E\\<e\\>M\\<m\\> | {k['doc']} |")
            continue
        rng = f"{k['min']} .. {k['max']}" + (", a power of two" if k["pow2"] else "")
        keys.append(f"| `{k['name']}` | {rng} | {k['doc']} |")
    keys += ["", "| derived | = | meaning |", "|---|---|---|"]
    keys += [f"| `{d['name']}` | `{d['expr'].text}` | {d['doc']} |" for d in schema.derived]
    keys += ["", "| rule | message |", "|---|---|"]
    keys += [f"| `{r['expr'].text}` | {r['message']} |" for r in schema.rules]
    names = [r["name"] for r in resolved]
    named = ["| | " + " | ".join(names) + " |", "|---|" + "---|" * len(names)]

    def row(label: str, cell) -> None:
        named.append(f"| {label} | " + " | ".join(cell(r["values"]) for r in resolved) + " |")
    row("shader cores x threads (chunk)", lambda v: f"{v['shader_cores']} x {v['threads_per_core']} ({v['chunk_size']})")
    row("lanes issued a cycle (issue_lanes)", lambda v: str(v["issue_lanes"]))
    row("registers", lambda v: str(v["registers"]))
    row("traversal units (ray slots each) / intersection units",
        lambda v: f"{v['traversal_units']} ({v['tu_slots']}) / {v['intersection_units']}")
    row("traversal units' kind", lambda v: (f"pipelined, {v['tu_setups']} set-up engines" if v["tu_pipe"]
                                            else "walkers"))
    row("rays a packet (tu_packet), memory answered (tu_by_tag)",
        lambda v: f"{v['tu_packet']}, {'by tag' if v['tu_by_tag'] else 'in order'}")
    row("node and triangle cache pairs (ray_caches)",
        lambda v: (f"{v['ray_caches']}, one a ray unit" if v["ray_caches"] == v["traversal_units"]
                   else "1, shared by the ray units" if v["ray_caches"] == 1
                   else f"{v['ray_caches']}, of {v['traversal_units'] // v['ray_caches']} ray units each"))
    row("sfu: threads at once (sfu_threads) x dividers (sfu_units)", lambda v: f"{v['sfu_threads']} x {v['sfu_units']}")
    row("stack depth, call depth, stack bytes", lambda v: f"{v['stack_depth']}, {v['call_depth']}, {v['stack_bytes']}")
    row("clock", lambda v: f"{v['clock_mhz']} MHz")
    row("format", lambda v: v["format"])
    for cache in ("node_cache", "triangle_cache", "data_cache"):
        row(cache.replace("_", " "), lambda v, c=cache: f"{_size(v[c + '.bytes'])}, {v[c + '.ways']}-way, "
            f"{v[c + '.line_bytes']} B lines, {v[c + '.mshrs']} MSHRs"
            + (", write-back" if c == "data_cache" and v[c + ".write_back"] else ""))
    row("DRAM latency, bytes/cycle, banks, bank busy",
        lambda v: f"{v['dram.latency']}, {v['dram.bytes_per_cycle']}, {v['dram.banks']}, {v['dram.bank_busy']}")
    named.append("")
    named += [f"- `{r['name']}`: {r['doc']}" for r in resolved]
    return {"keys": "\n".join(keys), "named": "\n".join(named)}


def fill_doc(text: str, blocks: dict[str, str], path: str) -> str:
    for name, body in blocks.items():
        try:
            text = doc_blocks.replace(text, f"spec/gen.py: {name}", body, path)
        except doc_blocks.DocBlockError as e:
            raise ConfigError(str(e)) from e
    return text
