"""A mechanism's library as a Functional Mock-up Unit: FMI 2.0 or 3.0, Model Exchange and
Co-Simulation in one unit, with its C sources and the binary for this platform.

``write_fmu(library, path, version=...)`` writes NAME.fmu, a zip of
- ``modelDescription.xml``: every parameter (tunable, the model's example as its start), the
  states theta and theta_d with their derivatives, an input per load parameter (added to
  it: a controller drives the load), and as outputs each named point's x and y and the
  kinetic and potential energies, with names, units and descriptions from the model;
- ``sources/``: the library's C (NAME.c and the runtime), the FMI glue written once
  (runtime/fmi: the instance's core, codegen_fmi_core.c, and the version's front end,
  codegen_fmi2.c or codegen_fmi3.c) and the FMU's own descriptor, NAME_fmi.c, rendered here
  from templates/fmi (FMI 3.0: with buildDescription.xml);
- ``binaries/linux64/NAME.so`` (FMI 3.0: ``x86_64-linux``), compiled from those sources
  against FMI's standard headers, which fmpy ships: ``pip install 'mechvib[fmu]'``.
The initial state is an equilibrium of the analysis at rest (the first stable one, or the
one ``equilibrium`` indexes). A mechanism with several coordinates has a state per
coordinate and rate, named after its coordinates (``theta_1``, ``theta_1_d``).
"""
from __future__ import annotations

import hashlib
import json
import platform
import shutil
import subprocess
import tempfile
import zipfile
from pathlib import Path
from typing import Any

import numpy as np

from . import files, resources

#: A fixed time stamp for the zip's entries: the same FMU, byte for byte, from the same model.
STAMP = (2020, 1, 1, 0, 0, 0)


class FmuError(ValueError):
    """What stops an FMU from being written, in one line."""


def fmi_headers() -> Path:
    """FMI's standard headers (fmi2Functions.h, fmi3Functions.h and their includes), as fmpy
    ships them."""
    try:
        import fmpy
    except ImportError:
        raise FmuError("writing an FMU needs FMI's headers, which fmpy ships: "
                       "pip install 'mechvib[fmu]'") from None
    return Path(fmpy.__file__).parent / "c-code"


def library_sources(library: Any) -> tuple[Path, Path]:
    """The folders of a library's own C and of the runtime it was built with."""
    origin = library.origin
    if origin and origin[0] == "load_from":
        root = Path(origin[1])
    else:
        root = resources.generated()
    return root / library.PREFIX, root / resources.RUNTIME


def _coordinates(library: Any) -> list[tuple[str, str, str]]:
    """Each independent coordinate's variable name, unit and description."""
    spec = library.SPEC
    if library.dof > 1:
        return [(c["name"], c["unit"], c["description"]) for c in spec["coordinates"]]
    angle = next(f for f in spec["functions"] if f["name"] == "angular_acceleration")
    unit = "rad" if "[rad" in angle["inputs"][0]["description"] else "m"
    return [("theta", unit, "the independent coordinate")]


#: The FMU's outputs after each named point's x and y [m], in value-reference order: the one
#: list of them. Each is its variable's name, unit and description, and its value in
#: NAME_fmi.c's outputs() (model_fmi.c.j2): a C expression of the energies the library
#: returns there, T and V (gravity's and the springs').
ENERGY_OUTPUTS = (
    {"name": "kinetic_energy", "unit": "J", "description": "kinetic energy T", "value": "T"},
    {"name": "potential_energy", "unit": "J",
     "description": "potential energy V (gravity and springs)", "value": "V"},
)


def _variables(library: Any, start: list[float]) -> tuple[list[dict], dict]:
    """The ScalarVariables in value-reference order (codegen_fmi2.h's layout), and the
    indices (from 1) the ModelStructure lists."""
    spec, P = library.SPEC, len(library.PARAMETER_NAMES)
    var: list[dict] = []

    def add(name, causality, variability, description, unit=None, start=None, initial=None,
            derivative=None):
        var.append({"name": name, "vr": len(var), "causality": causality,
                    "variability": variability, "description": description, "unit": unit,
                    "start": None if start is None else repr(float(start)),
                    "initial": initial, "derivative": derivative})
        return len(var)

    for p in spec["parameters"]:
        add(p["name"], "parameter", "tunable", p["description"], p["unit"], p["example"], "exact")
    coordinates = _coordinates(library)
    states = [add(name, "local", "continuous", description, unit, x0, "exact")
              for (name, unit, description), x0 in zip(coordinates, start)]
    rates = [add(f"{name}_d", "local", "continuous", f"the rate of {name}", f"{unit}/s", 0.0,
                 "exact") for name, unit, _ in coordinates]
    derivatives = [add(f"der({var[i - 1]['name']})", "local", "continuous",
                       f"d {var[i - 1]['name']}/dt", f"{var[i - 1]['unit']}/s",
                       derivative=i, initial="calculated") for i in states + rates]
    units = dict((p["name"], p["unit"]) for p in spec["parameters"])
    for load in spec["loads"]:
        add(f"{load}_input", "input", "continuous",
            f"added to the parameter {load}: a load a controller drives", units[load], 0.0)
    outputs = []
    for point in spec["points"]:
        for axis in "xy":
            outputs.append(add(f"{point}.{axis}", "output", "continuous",
                               f"{axis} of the point {point}", "m", initial="calculated"))
    for energy in ENERGY_OUTPUTS:
        outputs.append(add(energy["name"], "output", "continuous", energy["description"],
                           energy["unit"], initial="calculated"))
    assert len(var) == P + 4 * library.dof + len(spec["loads"]) + len(outputs)
    return var, {"outputs": outputs, "derivatives": derivatives,
                 "initial_unknowns": sorted(outputs + derivatives)}


def _start_state(library: Any, equilibrium: int | None) -> list[float]:
    """The initial coordinates: an equilibrium of the example at rest (the first stable
    one, or the one ``equilibrium`` indexes, from 0, in the analysis' list: `mechvib fmu
    --equilibrium N`, which counts from 1 as `mechvib analyze` lists them, gives N - 1)."""
    found = library.analyze(None).equilibria
    if equilibrium is not None:
        if not found:
            raise FmuError(f"equilibrium={equilibrium}: the example has no equilibrium")
        if not 0 <= equilibrium < len(found):
            raise FmuError(f"equilibrium={equilibrium}: an index into the example's "
                           f"{len(found)} equilibri{'um' if len(found) == 1 else 'a'}, from 0 "
                           f"to {len(found) - 1} (`mechvib fmu --equilibrium N` counts from 1)")
        chosen = found[equilibrium]
    else:
        stable = [e for e in found if e.stability == "stable"]
        chosen = (stable or found or [None])[0]
    if chosen is None:
        return [0.0] * library.dof
    return [float(x) for x in np.atleast_1d(chosen.theta)]


#: The FMI versions written, each by its front end over the glue's core.
VERSIONS = ("2.0", "3.0")
#: The glue every FMU carries: the descriptor, the core, and the version's front end.
CORE = ("codegen_fmi.h", "codegen_fmi_core.h", "codegen_fmi_core.c")
FRONT_END = {"2.0": "codegen_fmi2.c", "3.0": "codegen_fmi3.c"}
PLATFORM = {"2.0": "linux64", "3.0": "x86_64-linux"}


def write_fmu(library: Any, path: str | Path, equilibrium: int | None = None,
              version: str = "2.0") -> Path:
    """NAME.fmu for a library (see the module docstring), FMI ``version`` 2.0 or 3.0; the
    path written."""
    from . import __version__

    path = Path(path)
    if path.suffix != ".fmu":
        raise FmuError(f"{path}: an FMU's name ends in .fmu")
    if version not in VERSIONS:
        raise FmuError(f"FMI {version}: the versions written are {', '.join(VERSIONS)}")
    headers = fmi_headers()
    own, runtime = library_sources(library)
    prefix = library.PREFIX
    theta0 = _start_state(library, equilibrium)
    variables, structure = _variables(library, theta0)
    units = sorted({v["unit"] for v in variables if v["unit"]} | {"s"})
    env = _templates()
    glue = [*CORE, FRONT_END[version]]
    sources = (sorted(p.name for p in own.glob("*.c")) + [f"{prefix}_fmi.c"]
               + [g for g in glue if g.endswith(".c")]
               + sorted(p.name for p in runtime.glob("*.c")))
    context = {"prefix": prefix, "PREFIX": prefix.upper(), "title": library.TITLE,
               "version": __version__, "sources": sources, "units": units,
               "variables": variables, "time_vr": len(variables), **structure}
    template = f"modelDescription{version[0]}.xml.j2"
    body = env.get_template(template).render(guid="{GUID}", **context)
    guid = "{" + str(_uuid_of(body)) + "}"
    description = body.replace("{GUID}", guid)
    index = {p: i for i, p in enumerate(library.PARAMETER_NAMES)}
    part = env.get_template("model_fmi.c.j2").render(
        guid=guid, starts=[repr(float(library.EXAMPLE[n])) for n in library.PARAMETER_NAMES],
        loads=[index[name] for name in library.SPEC["loads"]],
        initial=[repr(float(x)) for x in theta0] + ["0.0"] * library.dof,
        energy_outputs=ENERGY_OUTPUTS, n_outputs=len(structure["outputs"]), dof=library.dof,
        **context)
    with tempfile.TemporaryDirectory() as work:
        folder = Path(work) / "sources"
        folder.mkdir()
        for source in [*own.glob("*.[ch]"), *runtime.glob("*.[ch]"),
                       *(resources.runtime() / "fmi" / name for name in glue)]:
            shutil.copy(source, folder / source.name)
        (folder / f"{prefix}_fmi.c").write_text(part)
        if version == "3.0":   # FMI 3.0 lists the sources beside them
            (folder / "buildDescription.xml").write_text(
                env.get_template("buildDescription.xml.j2").render(**context))
        binary = Path(work) / f"{prefix}.so"
        _compile(folder, sources, headers, binary)
        _check_platform()
        entries = {"modelDescription.xml": description.encode(),
                   f"binaries/{PLATFORM[version]}/{prefix}.so": binary.read_bytes()}
        entries |= {f"sources/{p.name}": p.read_bytes() for p in sorted(folder.iterdir())}
        entries["documentation/index.txt"] = _readme(library, theta0, version).encode()
        archive = _zip(entries)
    path.parent.mkdir(parents=True, exist_ok=True)
    with files.replacing(path) as scratch:   # atomically: never a truncated FMU
        scratch.write_bytes(archive)
    return path


def _templates() -> Any:
    """templates/fmi as Jinja2 templates (jinja2: the [fmu] extra's)."""
    import jinja2

    return jinja2.Environment(loader=jinja2.FileSystemLoader(resources.templates() / "fmi"),
                              undefined=jinja2.StrictUndefined, trim_blocks=True,
                              lstrip_blocks=True, keep_trailing_newline=True)


def _uuid_of(text: str) -> str:
    digest = hashlib.sha256(text.encode()).hexdigest()
    return f"{digest[:8]}-{digest[8:12]}-{digest[12:16]}-{digest[16:20]}-{digest[20:32]}"


def _check_platform() -> None:
    if platform.system() != "Linux" or platform.machine() not in ("x86_64", "AMD64"):
        raise FmuError(f"binaries for {platform.system()} {platform.machine()} are not built "
                       "yet (x86-64 Linux only); the FMU's sources build anywhere")


def _compile(folder: Path, sources: list[str], headers: Path, binary: Path) -> None:
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        raise FmuError("no C compiler (cc) to build the FMU's binary")
    command = [cc, *resources.cflags("base", "optimize"), "-fPIC", "-shared",
               "-fvisibility=hidden", f"-I{folder}", f"-I{headers}",
               *(str(folder / s) for s in sources), "-lm", "-o", str(binary)]
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        raise FmuError(f"the FMU's binary did not build: {done.stderr.strip()[-500:]}")


def _zip(entries: dict[str, bytes]) -> bytes:
    import io

    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as archive:
        for name in sorted(entries):
            info = zipfile.ZipInfo(name, STAMP)
            info.compress_type = zipfile.ZIP_DEFLATED
            info.external_attr = 0o644 << 16
            archive.writestr(info, entries[name])
    return buffer.getvalue()


def _readme(library: Any, start: list[float], version: str) -> str:
    state = ", ".join(f"{name} = {x!r} {unit}" for (name, unit, _), x in
                      zip(_coordinates(library), start))
    return (f"{library.TITLE}: an FMU written by mechvib (FMI {version}, Model Exchange and "
            f"Co-Simulation).\nInitial state, at rest: {state}.\nParameters (SI units): "
            + json.dumps(library.EXAMPLE) + "\n")
