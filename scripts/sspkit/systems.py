"""The SSP systems of the co-simulation scenes, built from the scene objects of
scripts/cosim/scenes.py (their `params`, `init_inputs()`, `initial_state()`, `body()`): which FMUs
take part (the scene's connector variant, FMI 2.0, and one Body FMU per body), the parameter
values of each, and the connections between them. Nothing is copied by hand: one function per
scene names the components, and the helpers below translate the master's bodies (bodies.py:
AxesBody, RigidBody) into Body FMU parameters (docs/body.md).

The connector runs with cosim.extrapolation = EXTRAPOLATION (2, quadratic from the FMU's input
history: a Jacobi master hands it no input derivatives); with_extrapolation gives a System at
another setting, 0 (hold) being our master's `jacobi`.

Also here: which Body outputs make up the master's state (p, u) (`state_outputs`, `to_state`),
so that a tool's samples become a master.Result. Uses cosim (scenes, bodies, driver for the
model descriptions) and numpy; archive.py writes a System into an .ssp, tools.py runs one.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from cosim import driver
from cosim.bodies import AxesBody, RigidBody
from cosim.connectors import DIST
from cosim.scenes import SCENES

BODY = "Body"                     # the Body FMU: dist/Body.fmu
PARAMETER_SET = "scene"           # the name of every component's parameter set (Ecos: init(parameter_set=...))
NODE_KINDS = ("r", "q", "v", "w")  # a node's inputs a Body drives: r[i], q.*, v[i], w[i] (not dv, dw)
AXES = "xyz"
HELD = 0                          # cosim.extrapolation = 0: the nodes held over a step
# every connector's cosim.extrapolation in dist/ssp: quadratic, the nodes along their velocities
# and the accelerations the FMU takes from its input history, the most accurate setting a plain
# master gets at 1 ms on every scene but the belt (docs/ssp.md, scripts/ssp_extrapolation.py)
EXTRAPOLATION = 2


@dataclass
class Component:
    """One FMU of a system: its instance name, the model (dist/<model>.fmu) and the values of its
    parameters, by variable name."""
    name: str
    model: str
    params: dict = field(default_factory=dict)


@dataclass
class System:
    """A scene as a system: the connector component first, then the Body components; connections
    as (start element, output, end element, input); `body` names the Body component that is the
    master's body (node b), whose outputs are the scene's state."""
    scene: object
    components: list
    connections: list
    body: str

    @property
    def name(self):
        return self.scene.name

    @property
    def connector(self):
        return self.components[0]

    def component(self, name):
        return next(c for c in self.components if c.name == name)


def variables(model):
    """{name: fmpy ScalarVariable} of dist/<model>.fmu."""
    return {v.name: v for v in driver.model_description(model, DIST).modelVariables}


def node_inputs(model, node):
    """The inputs of `node` ('a' or 'b') of connector `model` that a Body drives, in model order,
    as (connector input, Body output): ('b.r[1]', 'r[1]'), ('b.q.w', 'q.w'), ..."""
    out = []
    for name, v in variables(model).items():
        head, _, rest = name.partition(".")
        if v.causality == "input" and head == node and rest.split("[")[0].split(".")[0] in NODE_KINDS:
            out.append((name, rest))
    return out


def start_values(model):
    """{name: start} of the model's Real inputs."""
    return {n: float(v.start) for n, v in variables(model).items()
            if v.causality == "input" and v.type == "Real"}


def node_state(scene, node, body=None, p=None, u=None):
    """The inputs of `node` as the master first sets them: the scene's init_inputs, overwritten
    by what the master's body writes at its initial state (body.inputs at t = 0), as
    {'r[1]': ..., 'q.w': ..., 'v[1]': ..., 'w[1]': ...} (the node prefix dropped)."""
    values = dict(scene.init_inputs())
    if body is not None:
        x = np.zeros(len(body.in_names))
        body.inputs(0.0, p, u, x)
        values.update(zip(body.in_names, (float(v) for v in x)))
    return {n[len(node) + 1:]: v for n, v in values.items() if n.startswith(node + ".")}


def start_params(state):
    """Body parameters start.* from a node state (missing entries: at the origin, unrotated, at
    rest)."""
    out = {}
    for i in (1, 2, 3):
        out[f"start.r[{i}]"] = state.get(f"r[{i}]", 0.0)
    for c, default in zip("wxyz", (1.0, 0.0, 0.0, 0.0)):
        out[f"start.q.{c}"] = state.get(f"q.{c}", default)
    for kind in "vw":
        for i in (1, 2, 3):
            out[f"start.{kind}[{i}]"] = state.get(f"{kind}[{i}]", 0.0)
    return out


def axes_body(scene, body):
    """Body FMU parameters (model 0) of the master's AxesBody at node b: each coordinate of the
    body free (dof 1) with its mass or moment of inertia and its ground spring, every other
    translation and rotation fixed (dof 0) at the node's initial value."""
    if not isinstance(body, AxesBody):
        raise TypeError(f"{scene.name}: expected an AxesBody, got {type(body).__name__}")
    p0, u0 = scene.initial_state()
    state = node_state(scene, "b", body, p0, u0)
    params = {"model": 0}
    masses = {float(m) for (kind, _), m in zip(body.coords, body.m) if kind == "r"}
    if len(masses) > 1:
        raise ValueError(f"{scene.name}: one Body has one mass, the scene's translations have {masses}")
    if masses:
        params["mass"] = masses.pop()
    free = set(body.coords)
    for kind in "rw":
        for i in (1, 2, 3):
            params[f"dof.{kind}[{i}]"] = 1 if (kind, i) in free else 0
            if (kind, i) not in free and state.get(f"{'v' if kind == 'r' else 'w'}[{i}]", 0.0) != 0.0:
                raise ValueError(f"{scene.name}: node b moves along a coordinate the body does not have")
    for (kind, i), m, k in zip(body.coords, body.m, body.kg):
        if kind == "w":
            params[f"inertia[{i}]"] = float(m)
            if k:
                raise ValueError(f"{scene.name}: the Body has no rotational ground spring")
        elif k:
            params[f"spring.k[{i}]"] = float(k)
    params.update(start_params(state))
    return params


def prescribed_body(scene, body):
    """Body FMU parameters (model 0) of the master's moving node a (AxesBody.node_a = (axis i,
    velocity)): translation i prescribed (dof 2) at that velocity from the node's initial
    position, everything else fixed there."""
    axis, velocity = body.node_a
    state = node_state(scene, "a")
    if state.get(f"r[{axis}]", 0.0) != 0.0 or state.get(f"v[{axis}]", velocity) != velocity:
        raise ValueError(f"{scene.name}: the master moves node a as r = v t from 0 at v = {velocity}")
    state[f"v[{axis}]"] = velocity
    params = {"model": 0}
    for kind in "rw":
        for i in (1, 2, 3):
            params[f"dof.{kind}[{i}]"] = 2 if (kind, i) == ("r", axis) else 0
    params.update(start_params(state))
    return params


def rigid_body(scene, body):
    """Body FMU parameters (model 1) of the master's RigidBody at node b."""
    if not isinstance(body, RigidBody):
        raise TypeError(f"{scene.name}: expected a RigidBody, got {type(body).__name__}")
    p0, u0 = scene.initial_state()
    params = {"model": 1, "mass": float(body.m), "rigid.maxTurn": float(body.max_turn)}
    params.update({f"inertia[{i + 1}]": float(j) for i, j in enumerate(body.J)})
    params.update({f"gravity[{i + 1}]": float(g) for i, g in enumerate(body.g)})
    params.update(start_params(node_state(scene, "b", body, p0, u0)))
    return params


def connector(scene, name):
    """The connector component: the scene's FMU parameters, and cosim.extrapolation =
    EXTRAPOLATION."""
    return Component(name, scene.variant, {**scene.params, "cosim.extrapolation": EXTRAPOLATION})


def with_extrapolation(system, extrapolation):
    """`system` with every connector's (every component with a cosim.extrapolation parameter)
    set to `extrapolation` (0 hold … 3 along the acceleration inputs, docs/physics.md)."""
    if extrapolation not in (0, 1, 2, 3):
        raise ValueError(f"cosim.extrapolation must be 0, 1, 2 or 3, not {extrapolation!r}")
    comps = [Component(c.name, c.model, {**c.params, "cosim.extrapolation": extrapolation})
             if "cosim.extrapolation" in c.params else c for c in system.components]
    return System(system.scene, comps, system.connections, system.body)


def couple(scene, conn, bodies):
    """The system of connector component `conn` and `bodies` {node: Body component}: each node's
    inputs from its Body's outputs, and the master's loads (body.load_names: b.f[i], b.m[i]) back
    into node b's Body. An input no Body drives must keep the connector's start value, as in the
    scene (checked)."""
    connections = []
    for node, comp in bodies.items():
        connections += [(comp.name, out, conn.name, inp) for inp, out in node_inputs(conn.model, node)]
    b = bodies["b"]
    connections += [(conn.name, load, b.name, load[2:]) for load in scene.body().load_names]
    driven = {inp for *_, end, inp in connections if end == conn.name}
    start = start_values(conn.model)
    for name, value in scene.init_inputs().items():
        if name not in driven and value != start[name]:
            raise ValueError(f"{scene.name}: input {name} = {value} is not the FMU's start "
                             f"{start[name]} and no Body drives it")
    return System(scene, [conn, *bodies.values()], connections, b.name)


# --- one function per scene -------------------------------------------------------------------
def belt(scene):
    """Belt: node a the belt (a Body prescribed along y at v_b), node b the mass on its spring."""
    body = scene.body()
    return couple(scene, connector(scene, "planar"),
                  {"a": Component("belt", BODY, prescribed_body(scene, body)),
                   "b": Component("mass", BODY, axes_body(scene, body))})


def bounce(scene):
    """Bounce: the mass (free along z) on a RadialThrust whose node a is fixed at the origin."""
    return couple(scene, connector(scene, "radialthrust"),
                  {"b": Component("mass", BODY, axes_body(scene, scene.body()))})


def puck(scene):
    """Puck: the disc (free along y and about x, inertia J) on a Planar fixed at the origin."""
    return couple(scene, connector(scene, "planar"),
                  {"b": Component("puck", BODY, axes_body(scene, scene.body()))})


def bushing_pendulum(scene):
    """Bushing pendulum: a rigid body under gravity on a Bushing fixed at the origin."""
    return couple(scene, connector(scene, "bushing"),
                  {"b": Component("pendulum", BODY, rigid_body(scene, scene.body()))})


BUILDERS = {"belt": belt, "bounce": bounce, "puck0": puck, "bushing_pendulum": bushing_pendulum}
NAMES = tuple(BUILDERS)


def system(name):
    """The System of scene `name` (one of NAMES)."""
    if name not in BUILDERS:
        raise KeyError(f"no SSP system for scene {name!r}; there are: {', '.join(NAMES)}")
    return BUILDERS[name](SCENES[name])


# --- from a tool's samples back to the master's state -----------------------------------------
def state_outputs(body):
    """The Body outputs from which the master's state (p, u) of `body` is rebuilt."""
    if isinstance(body, RigidBody):
        return (["r[1]", "r[2]", "r[3]", "q.w", "q.x", "q.y", "q.z"]
                + ["v[1]", "v[2]", "v[3]", "w[1]", "w[2]", "w[3]"])
    names = []
    for kind, i in body.coords:
        names += [f"r[{i}]", f"v[{i}]"] if kind == "r" else ["q.w", f"q.{AXES[i - 1]}", f"w[{i}]"]
    return list(dict.fromkeys(names))


def to_state(body, samples):
    """(p, u), arrays of N+1 rows, from `samples` {Body output: array of N+1}. A rotation of an
    AxesBody is its angle 2 atan2(q_i, q_w), unwrapped."""
    if isinstance(body, RigidBody):
        p = np.column_stack([samples[n] for n in state_outputs(body)[:7]])
        u = np.column_stack([samples[n] for n in state_outputs(body)[7:]])
        return p, u
    p, u = [], []
    for kind, i in body.coords:
        if kind == "r":
            p.append(samples[f"r[{i}]"])
            u.append(samples[f"v[{i}]"])
        else:
            p.append(np.unwrap(2.0 * np.arctan2(samples[f"q.{AXES[i - 1]}"], samples["q.w"])))
            u.append(samples[f"w[{i}]"])
    return np.column_stack(p), np.column_stack(u)
