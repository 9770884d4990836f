"""The GLSL view of the memory map for compiled shaders (spec/shaders.toml).

gen_glsl writes rpu_memory.glsl: one struct per record a buffer holds, the buffers at
their bindings, the framebuffer image and the acceleration structure. gen_cpp writes the
compiler's table of bindings. Field types come from the memory map's comments, whose
first word is the field's type by the convention stated at the top of memory_map.toml.
"""
from __future__ import annotations

import pathlib
import re

from names import camel

GLSL_TYPES = {"float4": ("vec4", 16), "fp32": ("float", 4), "u32": ("uint", 4), "i32": ("int", 4)}
ELEMENTS = {"vec4": 16, "vec2": 8, "float": 4, "uint": 4}
FIELD = re.compile(r"^([a-z_0-9]+)\s*=\s*[^#]*#\s*(\S+)")
SECTION = re.compile(r"^\[([a-z_0-9.]+)\]")


class GlslError(Exception):
    pass


def field_types(memory_map_text: str) -> dict[str, dict[str, str]]:
    """{section: {field: type word}} from the comments of `<field>_at = N  # type ...` lines."""
    types: dict[str, dict[str, str]] = {}
    section = None
    for line in memory_map_text.splitlines():
        if m := SECTION.match(line):
            section = m.group(1)
        elif section and (m := FIELD.match(line)) and m.group(1).endswith("_at"):
            types.setdefault(section, {})[m.group(1)[:-3]] = m.group(2)
    return types


def record_struct(section: str, table: dict, types: dict[str, str]) -> list[str]:
    where = f"spec/memory_map.toml [{section}]"
    fields = sorted((v, k[:-3]) for k, v in table.items() if k.endswith("_at"))
    out = [f"struct {camel(section)} {{"]
    at, pad = 0, 0
    for offset, name in fields:
        word = types.get(name)
        if word not in GLSL_TYPES:
            raise GlslError(f"{where}: field '{name}_at' has type '{word}' in its comment; the GLSL view "
                            f"knows {', '.join(GLSL_TYPES)}")
        glsl, size = GLSL_TYPES[word]
        if offset % min(size, 16):
            raise GlslError(f"{where}: {word} field '{name}_at' = {offset} is not {size}-byte aligned (std430)")
        while at < offset:
            out.append(f"  uint pad{pad};")
            at, pad = at + 4, pad + 1
        if at > offset:
            raise GlslError(f"{where}: field '{name}_at' = {offset} overlaps the field before it")
        out.append(f"  {glsl} {name};")
        at = offset + size
    while at < table["bytes"]:
        out.append(f"  uint pad{pad};")
        at, pad = at + 4, pad + 1
    return out + ["};", ""]


def block_name(buffer: dict) -> str:
    """The GLSL block rpu.glsl declares the buffer as; the compiler accepts only it there."""
    return "Rpu" + camel(buffer["name"])


def gen_glsl(spec: dict, memory_map_text: str, banner: str) -> str:
    types = field_types(memory_map_text)
    mm, shaders = spec["memory_map"], spec["shaders"]
    out = [f"// {banner}", "// The scene's records and buffers as compiled shaders see them (docs/shaders.md).", ""]
    for b in shaders["buffer"]:
        if "record" in b:
            out += record_struct(b["record"], mm[b["record"]], types.get(b["record"], {}))
    for b in shaders["buffer"]:
        block = block_name(b)
        if "record" in b:
            elem = camel(b["record"])
        else:
            elem = b["element"]
        member = f"{elem} {b['name']}_record" if b.get("single") else f"{elem} {b['name']}[]"
        out.append(f"layout(set = 0, binding = {b['binding']}, std430) readonly buffer {block} {{ {member}; }};")
    out += ["",
            f"layout(set = 0, binding = {shaders['framebuffer']['binding']}, rgba32f) uniform image2D framebuffer;",
            f"layout(set = 0, binding = {shaders['acceleration_structure']['binding']}) "
            "uniform accelerationStructureEXT scene_bvh;", ""]
    out += [f"const uint {section.upper()}_{k.upper()} = {v}u;" for section in ("light_kind",)
            for k, v in mm[section].items()]
    out += [f"const int RPU_{section.upper()}_{k.upper()} = {v};" for section in ("ray_offset",)
            for k, v in mm[section].items()]
    return "\n".join(out) + "\n"


def validate(spec: dict) -> None:
    mm, shaders = spec["memory_map"], spec["shaders"]
    bindings = {}
    for b in shaders["buffer"]:
        where = f"spec/shaders.toml buffer '{b.get('name', '?')}'"
        if ("record" in b) == ("element" in b):
            raise GlslError(f"{where}: give exactly one of record and element")
        if "record" in b and b["record"] not in mm:
            raise GlslError(f"{where}: record '{b['record']}' is not a section of spec/memory_map.toml")
        if "element" in b and b["element"] not in ELEMENTS:
            raise GlslError(f"{where}: element must be one of {', '.join(ELEMENTS)}")
        if "address" in b and b["address"] not in mm["launch"]:
            raise GlslError(f"{where}: address '{b['address']}' is not a field of [launch]")
        if ("address" in b) == (b["name"] == "launch"):
            raise GlslError(f"{where}: every buffer but 'launch' names its launch-block address")
        bindings.setdefault(b["binding"], b["name"])
    for other in ("framebuffer", "acceleration_structure"):
        bindings.setdefault(shaders[other]["binding"], other)
    if len(bindings) != len(shaders["buffer"]) + 2:
        raise GlslError("spec/shaders.toml: two interfaces share a binding")


def gen_cpp(spec: dict) -> list[str]:
    shaders, mm = spec["shaders"], spec["memory_map"]
    out = ["// Compiled shaders' descriptor set 0 (spec/shaders.toml): where each buffer's address is.",
           "struct ShaderBuffer {", "  std::string_view name;", "  std::uint32_t binding;",
           "  std::string_view block;  // the block rpu.glsl declares at the binding",
           "  bool in_launch_block;     // the address is the launch-block word at launch_word_at",
           "  std::uint32_t launch_word_at;", "};",
           f"inline constexpr std::array<ShaderBuffer, {len(shaders['buffer'])}> kShaderBuffers{{{{"]
    for b in shaders["buffer"]:
        at = mm["launch"][b["address"]] if "address" in b else 0
        out.append(f"    {{\"{b['name']}\", {b['binding']}u, \"{block_name(b)}\", {'true' if 'address' in b else 'false'}, "
                   f"{at}u}},")
    out += ["}};",
            f"inline constexpr std::uint32_t kShaderFramebufferBinding = {shaders['framebuffer']['binding']}u;",
            f"inline constexpr std::uint32_t kShaderAccelerationStructureBinding = "
            f"{shaders['acceleration_structure']['binding']}u;", ""]
    return out
