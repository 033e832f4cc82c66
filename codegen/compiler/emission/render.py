"""The emission plan through Jinja2 templates into C source files.

One cached environment with StrictUndefined: a missing template variable is an error,
never an empty string. Output depends only on the plan, the templates and the
generator's version, so regeneration is byte-for-byte reproducible.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import json

import jinja2
import sympy as sp

from ... import __version__, ccodes
from .interval import inline_tail, inputs_read, interval_body, singular_parts, split_program
from .multibody import MultibodyPlan
from .plan import CFunction, Plan
from .printer import CTarget, PrintedBody, print_body

BANNER = "generated file, do not edit"


@lru_cache(maxsize=None)
def environment(template_dir: str) -> jinja2.Environment:
    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(template_dir),
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        autoescape=False,
    )
    env.filters["prefix_with"] = lambda value, prefix: f"{prefix}{value}"
    env.filters["c_declaration"] = ccodes.declaration
    return env


@dataclass(frozen=True)
class RenderedFunction:
    name: str
    summary: str
    equation: str
    inputs: tuple
    outputs: tuple
    signature: str
    pointer_signature: str
    batch_signature: str
    batch_arrays: tuple[tuple[str, str], ...]
    batch_call: tuple[str, ...]
    kernel_signature: str
    kernel_work_signature: str   # used where the body is a double-double program
    kernel_bounds_signature: str  # the same with a bound on each output's error
    returns_value: bool          # the kernel returns its one output (see returns_value)
    body: PrintedBody
    n_out: int
    offsets: tuple[tuple[str, int], ...]  # where each output starts in the kernel's out[]
    failure: str                          # the status of a result that is not finite
    pointer_checks: tuple[str, ...]
    finite_checks: tuple[str, ...]
    copies: tuple[str, ...]
    may_be_singular: bool
    slot_modes: tuple[int, ...] = ()     # CFunction.slot_modes
    # the statements that evaluate it on each sign choice (CFunction.on_signs; choice 0
    # first): the public function runs those the model's conditions declare at its angle
    sign_calls: tuple[tuple[str, ...], ...] = ()
    own_call: str = ""                   # the statement evaluating it by its own kernel
    public: bool = True                  # False: a kernel on another sign choice only


def _arguments(f: CFunction, prefix: str, ctype: str,
               arrays_as_pointers: bool = False) -> tuple[list[str], list[str]]:
    """C parameter declarations: params and the inputs, and the outputs."""
    P = prefix.upper()

    def array(name, size):
        return f"*{name}" if arrays_as_pointers else f"{name}[{P}_{size}]"

    inputs = [f"const {prefix}_params *params"]
    inputs += [f"const {ctype} {array(a.name, a.size)}" if a.size else f"{ctype} {a.name}"
               for a in f.inputs]
    outputs = [f"{ctype} {array(o.name, o.size)}" if o.size else f"{ctype} *{o.name}"
               for o in f.outputs]
    return inputs, outputs


def signature(f: CFunction, prefix: str, ctype: str, arrays_as_pointers: bool = False) -> str:
    inputs, outputs = _arguments(f, prefix, ctype, arrays_as_pointers)
    return f"{prefix}_status {prefix}_{f.name}({', '.join(inputs + outputs)})"


def returns_value(f: CFunction) -> bool:
    """Whether f's kernel returns its one output rather than writing it through a pointer,
    which the kernel would have to keep across each libm call (thetaddot: 5 % of its time)."""
    return sum(len(o.exprs) for o in f.outputs) == 1 and f.arithmetic != "double-double"


def kernel_signature(f: CFunction, prefix: str, ctype: str, values: str = "") -> str:
    """The unchecked kernel: the inputs as the public function takes them, the outputs
    together in one array (one output: returned); with ``values`` (the size of a
    double-double program's values), the kernel that takes them from the caller
    (NAME_kernel_work)."""
    inputs, _ = _arguments(f, prefix, ctype)
    n_out = sum(len(o.exprs) for o in f.outputs)
    if returns_value(f):
        return f"{ctype} {prefix}_{f.name}_kernel({', '.join(inputs)})"
    name, extra = (f"{f.name}_kernel_work", f", codegen_dd v[{values}]") if values else (
        f"{f.name}_kernel", "")
    return f"void {prefix}_{name}({', '.join(inputs)}, {ctype} out[{n_out}]{extra})"


def kernel_bounds_signature(f: CFunction, prefix: str, ctype: str, values: str) -> str:
    """A double-double program's kernel that also bounds each output's error (bound[]), its
    values and their error bounds in the caller's memory (NAME_bounds_kernel_work)."""
    inputs, _ = _arguments(f, prefix, ctype)
    n_out = sum(len(o.exprs) for o in f.outputs)
    return (f"void {prefix}_{f.name}_bounds_kernel_work({', '.join(inputs)}, {ctype} out[{n_out}], "
            f"{ctype} bound[{n_out}], codegen_dd v[{values}], {ctype} e[{values}])")


def batch_signature(f: CFunction, prefix: str, ctype: str) -> str:
    args = ["size_t count", f"const {prefix}_params *params"]
    args += [f"const {ctype} *{a.name}" for a in f.inputs]
    args += [f"{ctype} *{o.name}" for o in f.outputs]
    args.append(f"{prefix}_status *statuses")
    return f"{prefix}_status {prefix}_{f.name}_batch({', '.join(args)})"


def _batch_call(f: CFunction, P: str) -> tuple[str, ...]:
    """Arguments of item i: the i-th value of a scalar, the i-th block of an array."""
    def at(name, size):
        return f"&{name}[i * {P}_{size}]" if size else None

    args = [at(a.name, a.size) or f"{a.name}[i]" for a in f.inputs]
    args += [at(o.name, o.size) or f"&{o.name}[i]" for o in f.outputs]
    return tuple(args)


def _own_call(f: CFunction, prefix: str) -> str:
    """The statement that writes f's outputs into out[] by its own kernel."""
    arguments = ", ".join(["params"] + [a.name for a in f.inputs])
    return (f"out[0] = {prefix}_{f.name}_kernel({arguments});" if returns_value(f)
            else f"{prefix}_{f.name}_kernel({arguments}, out);")


def _sign_calls(f: CFunction, plan: Plan) -> tuple[tuple[str, ...], ...]:
    """The C statements that write f's outputs into out[] on each sign choice (CFunction.
    on_signs): choice 0 its own kernel; choice k its source's kernel into a local, then
    the outputs of f's names from it (at slot k of a function given on every mode)."""
    if not f.on_signs:
        return ()
    prefix = plan.prefix
    calls = [(_own_call(f, prefix),)]
    for k, name in enumerate(f.on_signs, start=1):
        source, at = plan.sign_choice_source(f.name, k)
        angle = [a.name for a in f.inputs[:1]]
        rate = [a.name for a in f.inputs[1:]] or ["0"]   # (a rate the outputs do not use)
        inputs = ", ".join(["params"] + angle + (rate if len(source.inputs) > 1 else []))
        n_out = sum(len(o.exprs) for o in source.outputs)
        lines = [f"codegen_real on_choice[{n_out}];",
                 f"{prefix}_{name}_kernel({inputs}, on_choice);"]
        found = plan.on_sign_choice(f.name, k)
        slot = 0
        for o in found.outputs:
            if o.name in at:
                lines += [f"out[{slot + i}] = on_choice[{at[o.name] + i}];"
                          for i in range(len(o.exprs))]
            else:   # vibration: K / M and B / (2 M), as its own expressions are
                M, B, K = (f"on_choice[{at[x]}]" for x in "MBK")
                lines.append(f"out[{slot}] = {K} / {M};" if o.name == "omega_n_squared"
                             else f"out[{slot}] = {B} / (2 * {M});")
            slot += len(o.exprs)
        calls.append(tuple(lines))
    return tuple(calls)


def _rendered(f: CFunction, plan: Plan, target: CTarget, public: bool = True
              ) -> RenderedFunction:
    P = plan.prefix.upper()
    copies, offsets, offset = [], [], 0
    for out in f.outputs:
        n = len(out.exprs)
        copies.append(f"copy_out({out.name}, out + {offset}, {n});" if out.size
                      else f"*{out.name} = out[{offset}];")
        offsets.append((out.name, offset))
        offset += n
    may_be_singular = any(_has_denominator(e) for o in f.outputs for e in o.exprs)
    return RenderedFunction(
        name=f.name, summary=f.summary, equation=f.equation, inputs=f.inputs,
        outputs=f.outputs,
        signature=signature(f, plan.prefix, target.ctype),
        pointer_signature=signature(f, plan.prefix, target.ctype, arrays_as_pointers=True),
        batch_signature=batch_signature(f, plan.prefix, target.ctype),
        kernel_signature=kernel_signature(f, plan.prefix, target.ctype),
        kernel_work_signature=kernel_signature(
            f, plan.prefix, target.ctype, f"{P}_{f.name.upper()}_VALUES"),
        kernel_bounds_signature=kernel_bounds_signature(
            f, plan.prefix, target.ctype, f"{P}_{f.name.upper()}_VALUES"),
        batch_arrays=tuple((x.name, x.size) for x in f.inputs + f.outputs),
        batch_call=_batch_call(f, P),
        body=print_body(f, plan.reads, target),
        n_out=offset,
        returns_value=returns_value(f),
        offsets=tuple(offsets),
        failure=f"{P}_ERR_{'SINGULAR_STATE' if may_be_singular else 'OVERFLOW'}",
        pointer_checks=tuple(a.name for a in f.inputs if a.size)
        + tuple(o.name for o in f.outputs),
        finite_checks=tuple(f"all_finite({a.name}, {P}_{a.size})" if a.size
                            else f"isfinite({a.name})" for a in f.inputs),
        copies=tuple(copies),
        may_be_singular=may_be_singular,
        slot_modes=f.slot_modes,
        own_call=_own_call(f, plan.prefix),
        sign_calls=_sign_calls(f, plan) if public else (),
        public=public,
    )


def _has_denominator(expr) -> bool:
    """Whether an expression divides by something that may vanish (a negative power)."""
    return any(p.exp.is_negative for p in sp.sympify(expr).atoms(sp.Pow)) or expr.has(sp.atan2)


#: Each mode's interval programs, by the name of their C function: G and G', G alone, and
#: the divisions and roots alone (whether G is smooth: its flags).
_ENCLOSURE_KINDS = (("body", "enclose_mode"), ("value", "enclose_value_mode"),
                    ("smooth", "enclose_smooth_mode"))


def _enclosure(plan: Plan) -> dict:
    """Each mode's interval programs (_ENCLOSURE_KINDS), and how the modes are labelled."""
    enclosure = plan.enclosure
    names = tuple(symbol for symbol, _ in plan.reads)
    theta = enclosure.theta.name
    assembly = [i for i, kind in enumerate(plan.root_kinds) if kind == "assembly"]
    modes = []
    for k, (g, dg) in enumerate(zip(enclosure.residuals, enclosure.slopes)):
        g = sp.sympify(g)
        bodies = {"body": [g, sp.sympify(dg)], "value": [g],   # G alone: cheaper
                  "smooth": singular_parts(g, enclosure.definitions) or [sp.S.Zero]}
        mode = {kind: interval_body(exprs, names, {theta}, enclosure.definitions)
                for kind, exprs in bodies.items()}
        flipped = [f"root {i} negative" for n, i in enumerate(assembly) if k >> n & 1]
        mode["label"] = ", ".join(flipped) or "as declared"
        modes.append(mode)
    programs = [m[kind].program for m in modes for kind, _ in _ENCLOSURE_KINDS]
    # theta's operations apart from the parameters' (run once per parameter set), the
    # latter's values in slots [0, fixed) below every program's own
    fixed = sum(split_program(p, {theta}, 0, 0).n_fixed for p in programs)
    first = 0
    for m in modes:
        for kind, _ in _ENCLOSURE_KINDS:
            split = split_program(m[kind].program, {theta}, first, fixed)
            first += split.n_fixed
            m[f"{kind}_split"] = {"head": split.head, "tail": split.tail,
                                  "head_inputs": inputs_read(split.head),
                                  "tail_inputs": inputs_read(split.tail),
                                  "inline": inline_tail(split.tail, {theta}, "iv_flags")}
    heads = [(f"{function}_{n}", m[f"{kind}_split"])
             for n, m in enumerate(modes) for kind, function in _ENCLOSURE_KINDS
             if m[f"{kind}_split"]["head"].instructions]
    slots = fixed + max(p.n_slots for p in programs)
    instructions = sum(len(p.instructions) for p in programs)
    return {"theta": theta, "equation": enclosure.equation, "modes": modes, "slots": slots,
            "fixed": fixed, "heads": heads, "inline": instructions <= INLINE_INSTRUCTIONS}


#: Interval programs (every mode's, in all) up to this many instructions are also written as
#: inline code, for CODEGEN_INLINE_INTERVALS: a four-bar's 2 500 compile in seconds; a
#: six-bar's 17 000 took gcc -O2 40 s (of 5 s for the rest of its library).
INLINE_INSTRUCTIONS = 8000


def _range_centre(plan: Plan, printer, text: str | None = None) -> str:
    """The centre of a coordinate's range (``text``, default the plan's one) as C, parameters
    read from params (the text names them as the user does: any name is a symbol here,
    ``sin`` or ``E`` too)."""
    fields = [field for _, field in plan.reads]
    centre = sp.sympify(plan.range_centre if text is None else text,
                        locals={f: sp.Symbol(f) for f in fields})
    return printer.doprint(centre.xreplace(
        {s: sp.Symbol(f"params->{s.name}") for s in centre.free_symbols}))


#: The runtime's name for the failure of each kernel it calls (codegen_model.h), and the
#: plan's function: only those the plan has are given.
_FAILURES = (("residual_failure", "equilibrium_residual"),
             ("linearisation_failure", "linearisation"),
             ("mode_linearisation_failure", "mode_linearisation"),
             ("radicands_failure", "radicands"),
             ("branches_failure", "equilibrium_branches"),
             ("sigma_failure", "sigma"),
             ("acceleration_failure", "angular_acceleration"))


def _model_layout(plan: Plan, functions: list[RenderedFunction]) -> dict:
    """What the library's codegen_model says of the fused state kernel's output (its size,
    and each quantity's field of codegen_state_layout) and of the kernels' failures."""
    state = next(f for f in functions if f.name == "equilibrium_state")
    return {"state_size": state.n_out,
            "state_offsets": [name.lower() for name, _ in state.offsets],
            "failures": [(field, name) for field, name in _FAILURES if plan.has(name)]}


def _library_context(plan: Plan, target: CTarget) -> dict:
    """What every library's templates read, of either kind: names, statuses, parameters,
    their requirements and the rendered functions."""
    prefix, P = plan.prefix, plan.prefix.upper()
    printer = target.printer
    used = sorted({s.name for r in plan.requirements for s in r.condition.free_symbols})
    return {
        "banner": BANNER, "version": __version__, "prefix": prefix, "PREFIX": P,
        "header": f"{prefix}.h", "source": f"{prefix}.c", "guard": f"{P}_H",
        "title": f"Vibration analysis of {plan.title}.",
        "statuses": [{"name": f"{P}_{s.suffix}", "value": s.value, "message": s.message}
                     for s in plan.statuses],
        "parameters": plan.parameters,
        "singular_state": plan.singular_state,
        "requirement_unpack": [(symbol, f"params->{field}") for symbol, field in plan.reads
                               if symbol in used],
        "fields": dict(plan.reads),   # a parameter's symbol -> its field of PREFIX_params
        "requirements": [{"condition": printer.doprint(r.condition), "code": f"{P}_ERR_{r.code}"}
                         for r in plan.requirements],
        "functions": [_rendered(f, plan, target) for f in plan.functions],
        "mode_kernels": [_rendered(f, plan, target, public=False) for f in plan.mode_functions],
    }


def render(plan: Plan, template_dir: Path, target: CTarget = CTarget()) -> dict[str, str]:
    """File name -> text of every generated file."""
    env = environment(str(template_dir))
    prefix = plan.prefix
    # The source is stdio-free; size_t comes from stddef.h, included by the header.
    printer = target.printer
    enclosure = _enclosure(plan)
    context = _library_context(plan, target)
    functions = context["functions"]
    context |= {
        "kernels_header": f"{prefix}_kernels.h",
        "sizes": sorted(plan.sizes.items()),
        "sizes_map": plan.sizes,
        "polynomial": plan.has("sigma"),
        "double_double": any(f.arithmetic == "double-double" for f in plan.functions),
        "root_kinds": plan.root_kinds,
        "length_bits": sum(1 << j for j, k in enumerate(plan.root_kinds) if k == "length"),
        "mode_of_branch": plan.mode_of_branch,
        "other_modes": plan.has("mode_linearisation"),
        "condition_bits": plan.condition_bits,
        "branch_of_mode": [plan.mode_of_branch.index(k) if plan.mode_of_branch else 0
                           for k in range(plan.sizes["N_MODES"])],
        "enclosure": enclosure,
        "inline_intervals": enclosure["inline"],
        "periodic": plan.periodic,
        "range_centre": _range_centre(plan, printer),
        "scaling": plan.scaling,
        # sigma as a double-double program, whose values the analysis keeps in its workspace
        "sigma_values": any(f.name == "sigma" and f.body.program for f in functions),
        # the runtime's enums, as its headers declare them
        "enums": ccodes.enums(),
    }
    context.update(_model_layout(plan, functions))
    templates = {f"{prefix}.h": "library.h.j2", f"{prefix}.c": "library.c.j2",
                 f"{prefix}.cdef": "library.cdef.j2", f"{prefix}_kernels.h": "kernels.h.j2",
                 f"{prefix}_model.c": "model.c.j2"}
    files = {name: env.get_template(template).render(template=template, **context)
             for name, template in templates.items()}
    files[f"{plan.prefix}_api.json"] = api_spec(plan)
    return files


def api_spec(plan: Plan) -> str:
    """What the Python wrapper needs to call and document every function, as JSON: each
    input and output with its size and its description (units in brackets, as in the
    plan). Keys sorted, so the text depends only on the plan."""
    def arg(x):
        return {"name": x.name, "size": plan.sizes[x.size] if x.size else None,
                "description": x.description}

    spec = {
        "prefix": plan.prefix,
        "title": plan.title,
        "root_kinds": list(plan.root_kinds),
        "range_centre": plan.range_centre,
        "periodic": plan.periodic,
        "version": __version__,
        "parameters": [dict(zip(("name", "unit", "description", "example"), p))
                       for p in plan.parameters],
        "sizes": plan.sizes,
        "statuses": [{"name": s.suffix, "value": s.value, "message": s.message,
                      "parameters": list(s.parameters)} for s in plan.statuses],
        "functions": [{"name": f.name, "summary": f.summary, "equation": f.equation,
                       "inputs": [arg(a) for a in f.inputs],
                       "outputs": [arg(o) for o in f.outputs]} for f in plan.functions],
        "points": list(plan.points),
        "loads": list(plan.loads),
    }
    if isinstance(plan, MultibodyPlan):  # n coordinates, each with its range
        spec |= {"dof": plan.n, "range_centre": list(plan.centres), "periodic": list(plan.periodics),
                 "coordinates": [dict(zip(("name", "unit", "description"), c))
                                 for c in plan.coordinates],
                 "all_coordinates": [dict(zip(("name", "unit", "description"), c))
                                     for c in plan.all_coordinates]}
    return json.dumps(spec, indent=1, sort_keys=True) + "\n"


def render_multibody(plan: MultibodyPlan, template_dir: Path,
                     target: CTarget = CTarget()) -> dict[str, str]:
    """File name -> text of every generated file of a mechanism with n coordinates."""
    env = environment(str(template_dir))
    prefix, printer = plan.prefix, target.printer
    # the isolation's raw boxes, before undecided neighbours merge and the margins are cut
    sizes = plan.sizes | {"BOXES": 4 * (plan.sizes["MAX_EQUILIBRIA"] + plan.sizes["MAX_UNCERTAIN"])}
    context = _library_context(plan, target) | {
        "n": plan.n, "sizes": sorted(sizes.items()), "sizes_map": sizes,
        "coordinate_list": ", ".join(name for name, _, _ in plan.coordinates),
        "range_list": "; ".join(
            f"{name} about {c}{' (periodic)' if periodic else ''}"
            for (name, _, _), c, periodic in zip(plan.coordinates, plan.centres, plan.periodics)),
        "polynomial": False, "double_double": False,
        "box": plan.box,
        "theta_index": {name: k for k, name in enumerate(plan.theta_names)},
        "centres": [_range_centre(plan, printer, c) for c in plan.centres],
        "periodics": [int(p) for p in plan.periodics],
    }
    templates = {f"{prefix}.h": ("multibody.h.j2", "codegen_real"),
                 f"{prefix}.c": ("multibody.c.j2", "codegen_real"),
                 f"{prefix}.cdef": ("multibody.cdef.j2", "double")}
    files = {name: env.get_template(template).render(template=template, real=real,
                                                     cdef=name.endswith(".cdef"), **context)
             for name, (template, real) in templates.items()}
    files[f"{prefix}_api.json"] = api_spec(plan)
    return files
