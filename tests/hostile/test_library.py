"""Hostile input to the library: every bad value is an InputError (a ValueError) naming the field, before any work.

Each case is (call, the text the message must hold). The calls are cheap: they fail at construction,
or at the start of a run, before a step is taken; none may raise anything but an InputError.
"""

import numpy as np
import pytest

import deformable as dm
from deformable import scenes
from tests.conftest import flat_model, flat_scene
from validation.harness.backends import make_model

NAN, INF = float("nan"), float("inf")


def _nan_surface(a1, a2):
    return np.stack([a1, a2, np.full_like(a1, NAN)], axis=-1)


def _line(a1, a2):  # a degenerate surface: r_1 and r_2 are parallel
    return np.stack([a1 + a2, a1 + a2, 0 * a1], axis=-1)


def _run(backend="fd", steps=1, **kw):
    model = flat_model(backend, nodes=(5, 5))
    return dm.TimeStepper(model, 1e-3).run(kw.pop("X0", model.initial_state()), steps=steps, **kw)


MATERIAL = {
    "mu None": (lambda: dm.Material(mu=None), "Material.mu"),
    "mu text": (lambda: dm.Material(mu="abc"), "Material.mu"),
    "mu numeric text": (lambda: dm.Material(mu="1"), "Material.mu"),
    "mu zero": (lambda: dm.Material(mu=0), "Material.mu must be positive"),
    "mu negative field": (lambda: dm.Material(mu=np.array([[1.0, -1.0]])), "Material.mu must be positive"),
    "mu nan": (lambda: dm.Material(mu=NAN), "Material.mu must be finite"),
    "mu inf": (lambda: dm.Material(mu=INF), "Material.mu must be finite"),
    "mu bool": (lambda: dm.Material(mu=True), "Material.mu"),
    "mu complex": (lambda: dm.Material(mu=1j), "Material.mu"),
    "mu empty": (lambda: dm.Material(mu=[]), "Material.mu"),
    "mu ragged": (lambda: dm.Material(mu=[[1, 2], [3]]), "Material.mu"),
    "gamma None": (lambda: dm.Material(gamma=None), "Material.gamma"),
    "gamma negative": (lambda: dm.Material(gamma=-0.1), "Material.gamma must be non-negative"),
    "eta None": (lambda: dm.Material(eta=None), "Material.eta"),
    "eta negative": (lambda: dm.Material(eta=-1.0), "Material.eta must be non-negative"),
    "eta inf": (lambda: dm.Material(eta=1e400), "Material.eta must be finite"),
    "eta dict": (lambda: dm.Material(eta={"a": 1}), "Material.eta"),
    "eta asymmetric": (lambda: dm.Material(eta=[[1.0, 2.0], [3.0, 1.0]]), "Material.eta must be symmetric"),
    "eta 3x3 on a grid": (lambda: flat_scene(material=dm.Material(eta=np.ones((3, 3)))), "Material.eta has shape"),
    "xi None": (lambda: dm.Material(xi=None), "Material.xi"),
    "xi negative": (lambda: dm.Material(xi=-1e-3), "Material.xi must be non-negative"),
    "alpha nan": (lambda: dm.Material(alpha=NAN), "Material.alpha must be finite"),
    "beta text": (lambda: dm.Material(beta="stiff"), "Material.beta"),
    "mu field of the wrong grid": (lambda: flat_scene(material=dm.Material(mu=np.ones((4, 4)))),
                                   "Material.mu has shape"),
}

FORCES = {
    "gravity g text": (lambda: dm.Gravity(g="9.81"), "Gravity.g must be a number"),
    "gravity g None": (lambda: dm.Gravity(g=None), "Gravity.g"),
    "gravity g nan": (lambda: dm.Gravity(g=NAN), "Gravity.g must be finite"),
    "gravity g array": (lambda: dm.Gravity(g=[1.0, 2.0]), "Gravity.g"),
    "gravity direction zero": (lambda: dm.Gravity(direction=(0, 0, 0)), "Gravity.direction must be a non-zero"),
    "gravity direction 2-vector": (lambda: dm.Gravity(direction=(0, 1)), "Gravity.direction must be a finite 3"),
    "gravity direction text": (lambda: dm.Gravity(direction="down"), "Gravity.direction"),
    "gravity direction nan": (lambda: dm.Gravity(direction=(NAN, 0, -1)), "Gravity.direction"),
    "gravity time not callable": (lambda: dm.Gravity(time=5), "Gravity.time must be a callable"),
    "body force 2-vector": (lambda: dm.BodyForce(f=(1, 2)), "BodyForce.f"),
    "body force where not callable": (lambda: dm.BodyForce(where=3), "BodyForce.where"),
    "body force time text": (lambda: dm.BodyForce(time="x"), "BodyForce.time"),
    "edge load unknown edge": (lambda: dm.EdgeLoad("middle"), "EdgeLoad.edge"),
    "edge load edge list": (lambda: dm.EdgeLoad(["left"]), "EdgeLoad.edge"),
    "edge load edge None": (lambda: dm.EdgeLoad(None), "EdgeLoad.edge"),
    "edge load nan": (lambda: dm.EdgeLoad("left", f=(NAN, 0, 0)), "EdgeLoad.f"),
    "point load outside the sheet": (lambda: flat_scene(forces=[dm.PointLoad(at=(2.0, 2.0), f=(0, 0, 1))]),
                                     "lies outside"),
    "point load just outside": (lambda: flat_scene(forces=[dm.PointLoad(at=(1.0 + 1e-9, 0.5))]), "lies outside"),
    "point load at text": (lambda: dm.PointLoad(at="ab"), "PointLoad.at"),
    "point load at nan": (lambda: dm.PointLoad(at=(NAN, 0.0)), "PointLoad.at"),
    "point load f None": (lambda: dm.PointLoad(at=(0, 0), f=None), "PointLoad.f"),
    "spring stiffness text": (lambda: dm.Spring(at=(0, 0), stiffness="1"), "Spring.stiffness"),
    "spring stiffness negative": (lambda: dm.Spring(at=(0, 0), stiffness=-1.0), "Spring.stiffness"),
    "spring rest length nan": (lambda: dm.Spring(at=(0, 0), rest_length=NAN), "Spring.rest_length"),
    "spring anchor 2-vector": (lambda: dm.Spring(at=(0, 0), anchor=(1, 2)), "Spring.anchor"),
    "spring outside the sheet": (lambda: flat_scene(forces=[dm.Spring(at=(-0.5, 0.5))]), "lies outside"),
    "wind coefficient negative": (lambda: dm.Wind(coefficient=-1.0), "Wind.coefficient"),
    "wind velocity nan": (lambda: dm.Wind(velocity=(NAN, 0, 0)), "Wind.velocity"),
    "sinusoidal frequency nan": (lambda: dm.Sinusoidal(frequency=NAN), "Sinusoidal.frequency"),
    "sinusoidal amplitude text": (lambda: dm.Sinusoidal(amplitude="a"), "Sinusoidal.amplitude"),
}

SHEET = {
    "size zero": (lambda: dm.Sheet(size=(0, 1)), "Sheet.size"),
    "size negative": (lambda: dm.Sheet(size=(-1, 1)), "Sheet.size"),
    "size nan": (lambda: dm.Sheet(size=(NAN, 1)), "Sheet.size"),
    "size None": (lambda: dm.Sheet(size=None), "Sheet.size"),
    "size three": (lambda: dm.Sheet(size=(1, 2, 3)), "Sheet.size"),
    "size text": (lambda: dm.Sheet(size=("1", "1")), "Sheet.size"),
    "size 1e-300": (lambda: dm.Sheet(size=(1e-300, 1e-300)), "Sheet.size"),
    "nodes inf": (lambda: dm.Sheet(nodes=(INF, 8)), "Sheet.nodes"),
    "nodes nan": (lambda: dm.Sheet(nodes=(NAN, 8)), "Sheet.nodes"),
    "nodes fractional": (lambda: dm.Sheet(nodes=(3.5, 8)), "Sheet.nodes"),
    "nodes two": (lambda: dm.Sheet(nodes=(2, 8)), "at least 3"),
    "nodes None": (lambda: dm.Sheet(nodes=None), "Sheet.nodes"),
    "nodes text": (lambda: dm.Sheet(nodes="8x8"), "Sheet.nodes"),
    "nodes one int": (lambda: dm.Sheet(nodes=8), "Sheet.nodes"),
    "nodes bool": (lambda: dm.Sheet(nodes=(True, 8)), "Sheet.nodes"),
    "nodes beyond memory": (lambda: dm.Sheet(nodes=(10**7, 10**7)), "GB of memory"),
    "rest not a surface": (lambda: dm.Sheet(rest=5), "expected a surface"),
    "rest NaN (FD)": (lambda: make_model(flat_scene(sheet=dm.Sheet(nodes=(5, 5), rest=_nan_surface)), "fd"),
                      "rest metric G0 is not finite"),
    "rest NaN (FE)": (lambda: make_model(flat_scene(sheet=dm.Sheet(nodes=(5, 5), rest=_nan_surface)), "fe"),
                      "rest metric G0 is not finite"),
    "rest degenerate (FD)": (lambda: make_model(flat_scene(sheet=dm.Sheet(nodes=(5, 5), rest=_line)), "fd"),
                             "is not finite"),
    "rest degenerate (FE)": (lambda: make_model(flat_scene(sheet=dm.Sheet(nodes=(5, 5), rest=_line)), "fe"),
                             "is not finite"),
    "rest wrong shape": (lambda: make_model(flat_scene(sheet=dm.Sheet(nodes=(5, 5), rest=lambda a, b: a)), "fd"),
                         "surface callable returned shape"),
}

SCENE = {
    "forces not a list": (lambda: flat_scene(forces=dm.Gravity()), "Scene.forces must be a list"),
    "forces text": (lambda: flat_scene(forces="gravity"), "Scene.forces must be a list"),
    "forces hold a number": (lambda: flat_scene(forces=[dm.Gravity(), 5]), "is not a Gravity"),
    "constraints not a list": (lambda: flat_scene(constraints=dm.Pin("left")), "Scene.constraints must be a list"),
    "constraints hold a force": (lambda: flat_scene(constraints=[dm.Gravity()]), "is not a Pin"),
    "sheet None": (lambda: dm.Scene(None, dm.Material()), "Scene.sheet must be a Sheet"),
    "material dict": (lambda: dm.Scene(dm.Sheet(), {"mu": 1}), "Scene.material must be a Material"),
    "force model unknown": (lambda: flat_scene(force_model="tpbf88"), "Scene.force_model"),
    "force model list": (lambda: flat_scene(force_model=["tpbf87"]), "Scene.force_model"),
    "frozen without weights": (lambda: flat_scene(force_model="frozen"), "needs Material.alpha"),
    "rest metric nan": (lambda: flat_scene(rest_metric=NAN), "Scene.rest_metric"),
    "rest curvature asymmetric": (lambda: flat_scene(rest_curvature=[[0, 1], [0, 0]]), "Scene.rest_curvature"),
    "name None": (lambda: flat_scene(name=None), "Scene.name must be a string"),
    "pin unknown edge": (lambda: flat_model(constraints=[dm.Pin("middle")]), "unknown edge or corner"),
    "pin a number": (lambda: flat_model(constraints=[dm.Pin(5)]), "cannot select nodes"),
    "pin motion not callable": (lambda: dm.Pin("left", motion=5), "Pin.motion must be a callable"),
    "pin indices outside": (lambda: flat_model(constraints=[dm.Pin(np.array([[9, 9]]))]), "lie outside"),
    "pin fractional indices": (lambda: flat_model(constraints=[dm.Pin(np.array([[1.5, 1.0]]))]), "cannot select"),
    "pin selects nothing": (lambda: flat_model(constraints=[dm.Pin(lambda a1, a2: a1 > 5)]), "selects no node"),
    "slide unknown axis": (lambda: dm.Slide("left", "w"), "Slide.axis"),
    "slide three axes": (lambda: dm.Slide("left", ["x", "y", "z"]), "Slide.axis"),
    "clamp unknown edge": (lambda: dm.Clamp("middle"), "Clamp.where"),
    "clamp a number": (lambda: dm.Clamp(5), "Clamp.where"),
    "model of None (FD)": (lambda: make_model(None, "fd"), "needs a Scene"),
    "model of None (FE)": (lambda: make_model(None, "fe"), "needs a Scene"),
    "model beyond memory (FD)": (lambda: make_model(flat_scene(nodes=(300, 300)), "fd"), "needs about 1.44 GB"),
    "model beyond memory (FE)": (lambda: make_model(flat_scene(nodes=(150, 150)), "fe"), "needs about 1.44 GB"),
    "unknown backend": (lambda: make_model(flat_scene(), "fv"), "unknown backend"),
}

SCENE_CONFIG = {
    "nodes inf": (lambda: scenes.config("curtain", nodes=(INF, 8)), "nodes"),
    "gather 1": (lambda: scenes.config("curtain", gather=1.0), "gather"),
    "seed negative": (lambda: scenes.config("curtain", seed=-1), "seed"),
    "dt 1e-300": (lambda: scenes.config("curtain", dt=1e-300), "dt must be at least"),
    "scaled mu overflows": (lambda: scenes.config("curtain", fabric="", mu=1e308, scale=10.0), "scale * mu"),
    "unknown field": (lambda: scenes.config("flag", wavelength=0), "unknown key 'wavelength'"),
    "frequency text": (lambda: scenes.config("flag", frequency="fast"), "frequency"),
    "frozen without alpha, beta": (lambda: scenes.config("hanging", force_model="frozen"), "alpha > 0 or beta > 0"),
    "alpha under the variational model": (lambda: scenes.config("hanging", alpha=1.0), "frozen model's weights"),
    "alpha negative": (lambda: scenes.config("hanging", force_model="frozen", alpha=-1.0), "alpha"),
    "unknown scene": (lambda: scenes.config("tablecloth"), "unknown scene 'tablecloth'"),
    "nodes beyond memory": (lambda: scenes.build(scenes.config("curtain", nodes=(10**6, 10**6))), "GB of memory"),
}

TRACKERS = {
    "guard every 0": (lambda: dm.DivergenceGuard(every=0), "DivergenceGuard.every"),
    "guard every fractional": (lambda: dm.DivergenceGuard(every=1.5), "DivergenceGuard.every"),
    "guard stretch nan": (lambda: dm.DivergenceGuard(max_stretch=NAN), "DivergenceGuard.max_stretch"),
    "guard stretch below 1": (lambda: dm.DivergenceGuard(max_stretch=0.5), "greater than 1"),
    "guard stretch text": (lambda: dm.DivergenceGuard(max_stretch="2"), "DivergenceGuard.max_stretch"),
    "guard energy nan": (lambda: dm.DivergenceGuard(max_energy=NAN), "DivergenceGuard.max_energy"),
    "guard energy growth nan": (lambda: dm.DivergenceGuard(energy_growth=NAN), "DivergenceGuard.energy_growth"),
    "guard displacement negative": (lambda: dm.DivergenceGuard(max_displacement=-1.0), "max_displacement"),
    "energy monitor every 0": (lambda: dm.EnergyMonitor(every=0), "EnergyMonitor.every"),
    "progress bar every -1": (lambda: dm.ProgressBar(every=-1), "ProgressBar.every"),
    "callback not callable": (lambda: dm.Callback(5), "Callback.fn"),
    "callback every 0": (lambda: dm.Callback(print, every=0), "Callback.every"),
}

STEPPER = {
    "dt nan": (lambda: dm.TimeStepper(flat_model(), NAN), "dt must be positive and finite"),
    "dt text": (lambda: dm.TimeStepper(flat_model(), "fast"), "dt must be a positive number"),
    "dt 1e-300": (lambda: dm.TimeStepper(flat_model(), 1e-300), "dt must be at least"),
    "dt negative": (lambda: dm.TimeStepper(flat_model(), -1e-3), "dt must be positive"),
    "scheme unknown": (lambda: dm.TimeStepper(flat_model(), 1e-3, scheme="rk4"), "scheme must be one of"),
    "scheme a list": (lambda: dm.TimeStepper(flat_model(), 1e-3, scheme=["newmark"]), "scheme must be one of"),
    "solver unknown": (lambda: dm.TimeStepper(flat_model(), 1e-3, solver="umfpack"), "solver must be one of"),
    "model None": (lambda: dm.TimeStepper(None, 1e-3), "model must be a backend"),
    "newton unknown key": (lambda: dm.TimeStepper(flat_model(force_model="variational"), 1e-3, newton=dict(foo=1)),
                           "unknown key 'foo' in the newton settings"),
    "newton text": (lambda: dm.TimeStepper(flat_model(force_model="variational"), 1e-3, newton="x"),
                    "newton settings must be"),
    "newton rtol nan": (lambda: dm.TimeStepper(flat_model(force_model="variational"), 1e-3,
                                               newton=dict(rtol=NAN)), "newton rtol"),
    "dt_min text": (lambda: dm.TimeStepper(flat_model(force_model="variational"), 1e-3, dt_min="x"), "dt_min"),
    "semi-implicit for the variational model": (lambda: dm.TimeStepper(flat_model(force_model="variational"), 1e-3,
                                                                       scheme="semi-implicit"), "lags"),
    "steps inf": (lambda: _run(steps=INF), "steps must be a non-negative integer"),
    "steps nan": (lambda: _run(steps=NAN), "steps must be a non-negative integer"),
    "steps text": (lambda: _run(steps="5"), "steps must be a non-negative integer"),
    "steps fractional": (lambda: _run(steps=2.5), "steps must be a non-negative integer"),
    "steps negative": (lambda: _run(steps=-1), "steps must be a non-negative integer"),
    "steps beyond the cap": (lambda: _run(steps=10**9), "exceeds the cap"),
    "t_end nan": (lambda: _run(steps=None, t_end=NAN), "t_end must be finite"),
    "t_end text": (lambda: _run(steps=None, t_end="1"), "t_end must be a number"),
    "t_end 1e300": (lambda: _run(steps=None, t_end=1e300), "steps of dt"),
    "t_end 1e3 (a million steps beyond the cap)": (lambda: _run(steps=None, t_end=1e5), "exceeds the cap"),
    "t_end before the start": (lambda: _run(steps=None, t_end=-1.0), "t_end must be later"),
    "X0 of another shape": (lambda: _run(X0=np.zeros((3, 3))), "X0 has shape (3, 3)"),
    "X0 NaN": (lambda: _run(X0=np.full((25, 3), NAN)), "X0 must be finite"),
    "X0 None": (lambda: _run(X0=None), "X0"),
    "X0 text": (lambda: _run(X0="flat"), "X0"),
    "V0 NaN": (lambda: _run(V0=np.full((25, 3), NAN)), "V0 must be finite"),
    "V0 of another shape": (lambda: _run(V0=np.zeros((24, 3))), "V0 has shape"),
    "t0 nan": (lambda: _run(t0=NAN), "t0 must be finite"),
    "trackers not a list": (lambda: _run(trackers=dm.EnergyMonitor()), "trackers must be a list"),
    "trackers hold a number": (lambda: _run(trackers=[5]), "is not a tracker"),
    "resume not a state": (lambda: _run(resume="checkpoint.npz"), "resume must be a State"),
    "resume NaN state": (lambda: _run(resume=dm.State(t=0.0, X=np.full((25, 3), NAN), V=np.zeros((25, 3)))),
                         "resume.X must be finite"),
    "resume negative step": (lambda: _run(resume=dm.State(t=0.0, X=np.zeros((25, 3)), V=np.zeros((25, 3)), step=-2)),
                             "resume.step"),
    "variational X0 NaN (FE)": (lambda: dm.TimeStepper(flat_model("fe", nodes=(4, 4), force_model="variational"),
                                                       1e-3).run(np.full((64, 3), NAN), steps=1), "X0 must be finite"),
    "equilibrium load steps 0": (lambda: dm.equilibrium(flat_model(force_model="variational"),
                                                        flat_model(force_model="variational").initial_state(),
                                                        load_steps=0), "load_steps"),
}

CASES = {f"{group}: {name}": case for group, table in (
    ("material", MATERIAL), ("forces", FORCES), ("sheet", SHEET), ("scene", SCENE), ("scene config", SCENE_CONFIG),
    ("trackers", TRACKERS), ("stepper", STEPPER)) for name, case in table.items()}


@pytest.mark.parametrize("case", list(CASES))
def test_a_bad_value_is_an_input_error_naming_it(case):
    call, message = CASES[case]
    with pytest.raises(dm.InputError) as info:
        call()
    assert message in str(info.value)
    assert isinstance(info.value, ValueError) and len(str(info.value).splitlines()) == 1


def _model(backend, **scene):
    return flat_model(backend, nodes=(5, 5), **scene)


def _start(backend, steps=1, force_model="tpbf87", **kw):
    model = _model(backend, force_model=force_model)
    X0 = kw.pop("X0", model.initial_state())
    if callable(X0):
        X0 = X0(model)
    return dm.TimeStepper(model, 1e-3).run(X0, steps=steps, **kw)


def _shaped(fill, rows=None):
    return lambda model: np.full((model.ndof if rows is None else rows, 3), fill)


#: cases run on both backends: (call(backend), the text the message must hold)
ON_BOTH = {
    "model of a text": (lambda b: make_model("curtain", b), "needs a Scene"),
    "model beyond memory": (lambda b: make_model(flat_scene(nodes=(300, 300)), b), "more than the 1 GB this machine"),
    "rest NaN": (lambda b: make_model(flat_scene(sheet=dm.Sheet(nodes=(5, 5), rest=_nan_surface)), b),
                 "rest metric G0 is not finite"),
    "point load outside": (lambda b: _model(b, forces=[dm.PointLoad(at=(1.5, 0.5), f=(0, 0, 1))]), "lies outside"),
    "spring outside": (lambda b: _model(b, forces=[dm.Spring(at=(0.5, -0.1))]), "lies outside"),
    "pin outside": (lambda b: _model(b, constraints=[dm.Pin(np.array([[0, 7]]))]), "lie outside"),
    "mu field of the wrong grid": (lambda b: _model(b, material=dm.Material(mu=np.ones((3, 3)))),
                                   "Material.mu has shape"),
    "dt nan": (lambda b: dm.TimeStepper(_model(b), NAN), "dt must be positive and finite"),
    "dt 1e-300": (lambda b: dm.TimeStepper(_model(b), 1e-300), "dt must be at least"),
    "dt inf": (lambda b: dm.TimeStepper(_model(b), INF), "dt must be positive and finite"),
    "dt auto without weights": (lambda b: dm.TimeStepper(_model(b, material=dm.Material(eta=0.0)), "auto"),
                                "give dt"),
    "scheme unknown": (lambda b: dm.TimeStepper(_model(b), 1e-3, scheme="rk4"), "scheme must be one of"),
    "implicit scheme for tpbf87": (lambda b: dm.TimeStepper(_model(b, force_model="tpbf87"), 1e-3,
                                                            scheme="newmark"), "needs an energy"),
    "steps inf": (lambda b: _start(b, steps=INF), "steps must be a non-negative integer"),
    "steps beyond the cap": (lambda b: _start(b, steps=10**8), "exceeds the cap"),
    "t_end 1e300": (lambda b: _start(b, steps=None, t_end=1e300), "steps of dt"),
    "t_end before the start": (lambda b: _start(b, steps=None, t_end=-1.0), "t_end must be later"),
    "steps and t_end": (lambda b: _start(b, steps=3, t_end=1.0), "give exactly one of t_end and steps"),
    "X0 NaN": (lambda b: _start(b, X0=_shaped(NAN)), "X0 must be finite"),
    "X0 inf": (lambda b: _start(b, X0=_shaped(INF)), "X0 must be finite"),
    "X0 one row short": (lambda b: _start(b, X0=lambda m: np.zeros((m.ndof - 1, 3))), "X0 has shape"),
    "X0 NaN (variational)": (lambda b: _start(b, force_model="variational", X0=_shaped(NAN)), "X0 must be finite"),
    "V0 NaN (variational)": (lambda b: _start(b, force_model="variational", V0=np.full((1, 3), NAN)), "V0"),
    "resume NaN state": (lambda b: _start(b, resume=dm.State(t=0.0, X=np.full((4, 3), NAN), V=np.zeros((4, 3)))),
                         "resume.X"),
    "trackers a guard, not a list": (lambda b: _start(b, trackers=dm.DivergenceGuard()), "trackers must be a list"),
    "writer of a .txt": (lambda b: dm.XDMFWriter("out.txt"), "must end in .xdmf"),
    "writer every 0": (lambda b: dm.XDMFWriter("out.xdmf", every=0), "XDMFWriter.every"),
    "writer interval nan": (lambda b: dm.XDMFWriter("out.xdmf", interval=NAN), "XDMFWriter.interval"),
    "writer interval negative": (lambda b: dm.XDMFWriter("out.xdmf", interval=-0.1), "XDMFWriter.interval"),
    "checkpoint writer every 0": (lambda b: dm.CheckpointWriter(".", "c", 0, np.zeros((4, 3))), "checkpoint-every"),
    "equilibrium load steps 0": (lambda b: dm.equilibrium(_model(b, force_model="variational"),
                                                          _model(b, force_model="variational").initial_state(),
                                                          load_steps=0), "load_steps"),
    "equilibrium with wind": (lambda b: dm.equilibrium(_model(b, force_model="variational", forces=[dm.Wind()]),
                                                       _model(b, force_model="variational").initial_state()),
                              "not conservative"),
}


@pytest.mark.parametrize("backend", ["fd", "fe"])
@pytest.mark.parametrize("case", list(ON_BOTH))
def test_a_bad_value_is_an_input_error_on_both_backends(case, backend):
    call, message = ON_BOTH[case]
    with pytest.raises(dm.InputError) as info:
        call(backend)
    assert message in str(info.value)
    assert isinstance(info.value, ValueError) and len(str(info.value).splitlines()) == 1


def _singular(*args, **kwargs):
    raise RuntimeError("Factor is exactly singular")  # what SuperLU raises


def _singular_pardiso(*args, **kwargs):
    from deformable.errors import SingularMatrix

    raise SingularMatrix("PARDISO: failed")  # what the wrapper makes of a PyPardisoError


@pytest.mark.parametrize("backend", ["fd", "fe"])
@pytest.mark.parametrize("force_model", ["tpbf87", "variational"])
def test_a_singular_step_matrix_ends_the_run_as_diverged_never_a_scipy_error(backend, force_model, monkeypatch):
    """Every factorisation fails from the third step on (a stepper of its own, resumed at step 2): the run ends
    "diverged" with the state of step 2."""
    model = _model(backend, force_model=force_model, forces=[dm.Gravity()], constraints=[dm.Pin("top")])
    stepper = dm.TimeStepper(model, 1e-3)
    first = stepper.run(model.initial_state(), steps=2)
    monkeypatch.setattr("scipy.sparse.linalg.splu", _singular)
    monkeypatch.setattr("deformable.algebra.solvers.spla.splu", _singular)
    monkeypatch.setattr("deformable.algebra.solvers.Pardiso.factor", _singular_pardiso)
    bent = dm.State(t=first.state.t, X=first.state.X + 0.05 * np.random.default_rng(1).standard_normal(
        first.state.X.shape), V=first.state.V, step=2)  # elastic forces: Newton has to factorise
    fresh = dm.TimeStepper(model, 1e-3)  # no factorisation to reuse
    result = fresh.run(model.initial_state(), steps=5, resume=bent)
    assert result.status == "diverged" and "singular" in result.message
    assert result.state.step == 2
    np.testing.assert_array_equal(result.state.X, bent.X)
