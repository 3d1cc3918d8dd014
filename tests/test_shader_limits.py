"""Every shader program the renderer builds fits the uniform storage of the GPUs it must run on.

llvmpipe, the renderer of the test machines, gives a stage far more uniform storage than a GPU: NVIDIA's drivers
give each stage 1024 vector registers (GL_MAX_VERTEX_UNIFORM_VECTORS, GL_MAX_FRAGMENT_UNIFORM_VECTORS), and a
program declaring more fails to link there and draws nothing, while it links and draws here (the quick view did so
on a lent H200). So each program is taken as VTK compiles it (the source handed to the mapper's UpdateShaderEvent) and
its declared uniforms are counted under GLSL's default layout, which the drivers follow: every scalar or vector,
and every element of an array of them, takes a whole register; a matCxR takes C. Declared, not active: a compiler
drops unused uniforms, so the count is an upper bound and the limit holds whatever a driver keeps. Samplers take no
register but a texture unit; 16 per stage is the OpenGL 3.2 core minimum (GL_MAX_TEXTURE_IMAGE_UNITS).
"""
import os
import re

import pytest

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")

from vtkmodules.util.misc import calldata_type  # noqa: E402
from vtkmodules.util.vtkConstants import VTK_OBJECT  # noqa: E402
from vtkmodules.vtkCommonCore import vtkCommand  # noqa: E402
from vtkmodules.vtkRenderingCore import vtkAssembly  # noqa: E402

from planetviz.render import Scene  # noqa: E402

UNIFORM_VECTORS = 1024
TEXTURE_UNITS = 16
SIZE = (64, 48)

_DEFINE = re.compile(r"^\s*#define\s+(\w+)\s+(.+?)\s*$", re.M)
_UNIFORM = re.compile(r"\buniform\s+(?:(?:highp|mediump|lowp)\s+)?(\w+)\s+([^;{]+);")
_DECLARATOR = re.compile(r"^(\w+)\s*(?:\[(.+)\])?$")


def _integer(expression, defines):
    """The value of an array size: integer literals, defined names and + - * / ( ), with GLSL's truncating
    integer division."""
    for _ in range(16):                         # defines may name defines
        expanded = re.sub(r"\b[A-Za-z_]\w*\b", lambda m: f"({defines[m.group(0)]})" if m.group(0) in defines
                          else m.group(0), expression)
        if expanded == expression:
            break
        expression = expanded
    if not re.fullmatch(r"[\d\s()+\-*/]+", expression):
        raise ValueError(f"array size {expression!r} is not an integer expression")
    return eval(expression.replace("/", "//"))


def _registers(glsl_type):
    """Vector registers of one scalar, vector or matrix of ``glsl_type``; 0 for a sampler."""
    if "sampler" in glsl_type:
        return 0
    matrix = re.fullmatch(r"d?mat(\d)(?:x\d)?", glsl_type)
    if matrix:
        return int(matrix.group(1))
    if re.fullmatch(r"(?:float|int|uint|bool|double|[biud]?vec[234])", glsl_type):
        return 1
    raise ValueError(f"uniform type {glsl_type!r} not known to the count")


def uniform_storage(source):
    """(vector registers, samplers) declared by the uniforms of one shader stage's ``source``."""
    source = re.sub(r"/\*.*?\*/", " ", source, flags=re.S)
    source = re.sub(r"//[^\n]*", "", source)
    defines = dict(_DEFINE.findall(source))
    registers = samplers = 0
    for glsl_type, declarators in _UNIFORM.findall(source):
        for declarator in declarators.split(","):
            name, size = _DECLARATOR.match(declarator.strip()).groups()
            count = _integer(size, defines) if size else 1
            registers += count * _registers(glsl_type)
            samplers += count if "sampler" in glsl_type else 0
    return registers, samplers


def test_the_count_follows_glsl_default_layout():
    source = ("#define N 5\n#define M ((N + 4) / 4)\n// uniform vec4 commented[100];\n"
              "uniform float a[N];\nuniform vec4 b[M], c;\nuniform mat4 d;\nuniform sampler2D e, f[2];\n"
              "/* uniform mat3 hidden; */ uniform highp int g;\n")
    assert uniform_storage(source) == (5 + 2 + 1 + 4 + 1, 3)


def _programs(scene):
    """{(actor class, stage): source} of every program drawn in a frame of ``scene``."""
    sources = {}
    mappers = []
    props = scene.renderer.GetViewProps()
    for i in range(props.GetNumberOfItems()):
        prop = props.GetItemAsObject(i)
        parts = prop.GetParts() if isinstance(prop, vtkAssembly) else None
        actors = [parts.GetItemAsObject(j) for j in range(parts.GetNumberOfItems())] if parts else [prop]
        mappers += [actor.GetMapper() for actor in actors if actor.GetMapper() is not None]

    def observer(owner):
        @calldata_type(VTK_OBJECT)
        def capture(caller, event, program=None):
            if program is not None:
                sources[(owner, id(caller), "vertex")] = program.GetVertexShader().GetSource()
                sources[(owner, id(caller), "fragment")] = program.GetFragmentShader().GetSource()
        return capture

    owner = type(scene.active_actor).__name__
    tags = [(m, m.AddObserver(vtkCommand.UpdateShaderEvent, observer(owner))) for m in mappers]
    scene.screenshot()
    for mapper, tag in tags:
        mapper.RemoveObserver(tag)
    return sources


@pytest.mark.parametrize("method,shading,tables", [("tables", "pixel", "4d"), ("tables", "vertex", "4d"),
                                                   ("tables", "pixel", "compact"), ("quick", "vertex", "4d")])
def test_every_program_fits_a_gpus_uniform_registers_and_texture_units(method, shading, tables):
    # Mars: three extinction components and dust with two lobes, the most the presets declare; the counts depend
    # on the format's limits (MAX_GROUPS, MAX_COMPONENTS, MAX_SAMPLES, the mesh), not on the atmosphere.
    scene = Scene("mars", quality="draft", surface="texture", off_screen=True, window_size=SIZE, method=method,
                  shading=shading, tables=tables)
    try:
        if method == "tables":
            scene.wait_for_tables()
        for view in ("space", "ground"):
            if view == "space":
                scene.view_from_space()
            else:
                scene.view_from_ground(pitch=5)
            programs = _programs(scene)
            assert any(stage == "vertex" for (_, _, stage) in programs), "no program of the planet was drawn"
            for (owner, _, stage), source in programs.items():
                registers, samplers = uniform_storage(source)
                assert registers <= UNIFORM_VECTORS, f"{owner} {stage} stage: {registers} uniform vectors"
                assert samplers <= TEXTURE_UNITS, f"{owner} {stage} stage: {samplers} samplers"
    finally:
        scene.close()
