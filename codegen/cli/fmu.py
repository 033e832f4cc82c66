"""`mechvib fmu`: the mechanism as a Functional Mock-up Unit for simulators."""
from __future__ import annotations

from . import common

#: --fmi's choices: codegen.fmu.VERSIONS (written here so that building the parser imports
#: none of codegen.fmu; tests/cli/test_lazy_imports.py holds the two equal).
VERSIONS = ("2.0", "3.0")

EXAMPLES = """\
examples:
  {prog} fmu --out doughty.fmu
  {prog} fmu --mechanism four_bar --equilibrium 2 --out four_bar.fmu
  {prog} fmu --model my_model.py --out mine.fmu
  {prog} fmu --mechanism double_pendulum --fmi 3.0 --out double_pendulum.fmu

Writes an FMU (FMI 2.0, or 3.0 with --fmi 3.0; Model Exchange and Co-Simulation in one unit)
of the mechanism: its parameters (tunable, the example as start values), each coordinate
and its rate as states, an input per load parameter (added to it), the named points'
positions and the energies as outputs;
the C sources, and the binary for this platform. The initial state is an equilibrium of the
example at rest (the first stable one, or --equilibrium N, numbered from 1 as `mechvib
analyze` lists them). Needs fmpy for FMI's standard headers: pip install 'mechvib[fmu]'."""


def run(args) -> int:
    from ..fmu import write_fmu
    from .report import paragraph

    library = common.load_library(args)
    chosen = None
    if args.equilibrium is not None:   # counted as `analyze` lists them; write_fmu's, from 0
        chosen = common.equilibrium_index(args.equilibrium,
                                          len(library.analyze(None).equilibria),
                                          library.PREFIX, "at its example's parameters")
    path = write_fmu(library, args.out, chosen, args.fmi)
    inputs, outputs = len(library.SPEC["loads"]), 2 * len(library.SPEC["points"]) + 2
    print(paragraph(f"Wrote {path}: an FMI {args.fmi} FMU (Model Exchange and Co-Simulation) of "
                    f"{library.TITLE}, with {len(library.PARAMETER_NAMES)} parameters, "
                    f"{inputs} input{'' if inputs == 1 else 's'} and {outputs} outputs."))
    return 0


def add(verbs, prog: str) -> None:
    fmu = common.verb(verbs, "fmu", "the mechanism as an FMU (FMI 2.0 or 3.0, Model Exchange "
                      "and Co-Simulation) for simulators", EXAMPLES, prog, run)
    common.mechanism_options(fmu, None, model=True)
    fmu.add_argument("--out", required=True, metavar="FILE.fmu", help="the FMU to write")
    fmu.add_argument("--fmi", choices=VERSIONS, default=VERSIONS[0],
                     help="the FMI version (default 2.0, which most tools take)")
    fmu.add_argument("--equilibrium", type=int, metavar="N",
                     help="start at the N-th equilibrium of the example, "
                          f"{common.EQUILIBRIUM_NUMBERING} (default: the first stable one)")
