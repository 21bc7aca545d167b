r"""Section 3.1, the damping regimes: one sheet mode against the mass-spring formula.

The paper reads eq. (11), ``mu r_tt + gamma r_t + e(r) = f``, as "a mass-coil
system at each point": gamma large against mu gives an over-damped return,
larger mu a damped oscillation, and gamma = 0 an oscillation that never ends.
On one mode of a sheet this is exact. A flat membrane pinned on its four
edges under the frozen model (section 3.2: alpha given directly, beta = 0)
is linear, ``M z'' + C z' + K z = 0`` for its transverse positions z, with
``C = (gamma / mu) M`` (scalar mu, gamma; both backends build C from the mass
form). The lowest eigenpair ``K phi = w0^2 M phi`` (M-normalised phi) is a
mass-spring system for the modal coordinate ``q = phi^T M z``::

    q'' + (gamma / mu) q' + w0^2 q = 0,   roots s = -zeta w0 +- w0 sqrt(zeta^2 - 1),  zeta = gamma / (2 mu w0),

over-damped for zeta > 1 (two real roots; the slow one, ``-w0 (zeta - sqrt(zeta^2 - 1))``, is the decay
rate), a damped oscillation of frequency ``w0 sqrt(1 - zeta^2)`` and decay rate ``zeta w0`` for
zeta < 1, and a lasting one at w0 for gamma = 0. The continuous membrane's w0 is
``sqrt(alpha pi^2 (1 / L1^2 + 1 / L2^2) / mu)``; the grid's eigenvalue differs from it by the space
discretisation, reported beside it.

A time scheme replaces each root s by the root z of its own recurrence, and
its numerical damping is ``-log|z| / dt - (-Re s)``. Starting from the mode
shape, q_n stays a sum of two powers z^n, and Prony's method (linear
prediction, R. de Prony 1795; Hildebrand, *Introduction to Numerical
Analysis*, sec. 9.4) recovers z from the samples: the least-squares
``q_{n+1} = c1 q_n + c2 q_{n-1}`` gives ``z^2 - c1 z - c2 = 0``; the measured
rate and frequency are ``-log|z| / dt`` and ``arg z / dt``. The schemes and
their predicted z (w = w0, c = gamma / mu):

- Newmark, beta = 1/4, gamma = 1/2 (the trapezoidal rule): ``z = (1 + s dt / 2) / (1 - s dt / 2)``,
  no numerical damping (|z| = 1 for gamma = 0), a frequency error ``O((w dt)^2 / 12)``;
- implicit Euler (the shipped scenes' scheme): ``z = 1 / (1 - s dt)``, damping ``w^2 dt / 2`` at gamma = 0;
- the paper's semi-implicit step, eq. (22)-(27) with ``V_t = (R_t - R_{t-dt}) / dt``:
  ``(1 + c dt / 2 + w^2 dt^2) z^2 - 2 z + (1 - c dt / 2) = 0``, at gamma = 0
  ``|z| = (1 + w^2 dt^2)^(-1/2)`` (docs/design.md, "Time stepping"): damping about ``w^2 dt / 2`` too.

So the measured rate and frequency are compared with two predictions: the
scheme's root (agreement to the solver's precision: the measurement works),
and the continuous formula (agreement to the scheme's error: Newmark at
``w0 dt = 2 pi / STEPS_PER_PERIOD`` is within ``(w0 dt)^2`` of it; the
first-order schemes are not, by their numerical damping).

"gamma = 0 keeps oscillating" is judged by the amplitude the mode keeps over
one period of its measured oscillation, ``|z|^(2 pi / |arg z|) = exp(-2 pi
rate / freq)``, computed from the measured root. The mode *keeps oscillating*
(the paper: "keeps oscillating around an equilibrium point", against the damped
oscillation that reaches equilibrium) when it loses at most :data:`LOSS_KEPT`
of its amplitude a period. At gamma = 0 under the paper's step the prediction
is ``(1 + (w0 dt)^2)^(-pi / (w0 dt))``, about ``exp(-pi w0 dt)`` = 0.74 at 64
steps a period: a loss of 26 % a period, an under-damped oscillation whose
damping is the scheme's, not gamma's (the same under implicit Euler; none
under the trapezoidal rule, which conserves the energy of a linear
oscillator: Newmark 1959; Hughes, *The Finite Element Method*, 1987, ch. 9).
"""

from __future__ import annotations

import cmath
import math

import numpy as np
import scipy.linalg as sla

import deformable as dm
from deformable.algebra.solvers import one_blas_thread
from validation.harness.backends import BACKENDS, make_model
from validation.harness.study import Table

from .claims import Claim, checks_of

__all__ = ["DAMPING", "REGIMES", "SCHEMES", "LOSS_KEPT", "membrane", "lowest_mode", "mass_spring_roots",
           "scheme_root", "prony", "rate_and_frequency", "amplitude_per_period", "undamped_claim", "run_mode",
           "measure"]

#: the membrane: size (m), mu (kg/m^2), alpha (N/m), nodes a side (FD; FE: elements + 1), amplitude (m)
DAMPING = dict(size=(1.0, 0.8), mu=0.2, alpha=1.0, nodes={"fd": 9, "fe": 5}, amplitude=0.01)
#: damping ratio zeta = gamma / (2 mu w0) of each regime of section 3.1
REGIMES = {"over-damped": 2.0, "damped oscillation": 0.1, "undamped": 0.0}
#: the time schemes, and how many steps a period of the undamped mode takes (w0 dt = 2 pi / STEPS_PER_PERIOD)
SCHEMES = ("newmark", "implicit-euler", "semi-implicit")
#: the schemes as the claims table names them
SCHEME_NAMES = {"newmark": "Newmark's trapezoidal rule", "implicit-euler": "implicit Euler",
                "semi-implicit": "the paper's semi-implicit step (eq. 22-27)"}
STEPS_PER_PERIOD = 64
#: how long each run lasts, in periods 2 pi / w0
PERIODS = 4
#: an oscillation "keeps oscillating" (section 3.1, gamma = 0) when it loses at most this fraction of its
#: amplitude a period (the study's threshold of a visible change, validation.studies.paper.cases.VISIBLE)
LOSS_KEPT = 1e-2


def membrane(nodes: int, gamma: float = 0.0, p: dict = DAMPING) -> dm.Scene:
    """The flat membrane under the frozen model, pinned on its four edges, no load (module docstring)."""
    sheet = dm.Sheet(size=p["size"], nodes=(nodes, nodes))
    mat = dm.Material(mu=p["mu"], gamma=gamma, alpha=p["alpha"], beta=0.0)
    return dm.Scene(sheet, mat, constraints=[dm.Pin(["left", "right", "bottom", "top"])], force_model="frozen",
                    name="membrane")


def lowest_mode(model) -> tuple[float, np.ndarray]:
    """w0 (rad/s) and the M-normalised shape phi (ndof,) of the lowest transverse mode of a linear model."""
    fixed = model.fixed_dofs()[2]
    free = np.setdiff1d(np.arange(model.ndof), fixed)
    K = model.stiffness(model.initial_state()).toarray()[np.ix_(free, free)]
    M = model.mass().toarray()[np.ix_(free, free)]
    with one_blas_thread():  # its last bits would depend on OpenBLAS's threads: the same on every worker
        w2, vec = sla.eigh(K, M, subset_by_index=(0, 0))
    phi = np.zeros(model.ndof)
    phi[free] = vec[:, 0]
    phi *= np.sign(phi[np.argmax(np.abs(phi))])
    return math.sqrt(w2[0]), phi


def mass_spring_roots(w0: float, zeta: float) -> tuple[complex, complex]:
    """The roots s of ``s^2 + 2 zeta w0 s + w0^2 = 0`` (1/s), the slower-decaying one first."""
    d = cmath.sqrt(zeta * zeta - 1.0)
    return (-zeta + d) * w0, (-zeta - d) * w0


def scheme_root(scheme: str, w0: float, zeta: float, dt: float) -> complex:
    """The root z of a scheme's recurrence for the slower continuous root (module docstring)."""
    s = mass_spring_roots(w0, zeta)[0]
    if scheme == "newmark":
        return (1 + 0.5 * s * dt) / (1 - 0.5 * s * dt)
    if scheme == "implicit-euler":
        return 1 / (1 - s * dt)
    if scheme == "semi-implicit":
        c = 2.0 * zeta * w0
        roots = np.roots([1 + 0.5 * c * dt + (w0 * dt) ** 2, -2.0, 1 - 0.5 * c * dt])
        return complex(roots[np.argmax(np.abs(roots))])  # the slower-decaying one
    raise ValueError(f"unknown scheme {scheme!r}; expected one of {SCHEMES}")


def prony(q: np.ndarray) -> tuple[complex, complex]:
    """The two roots z of the least-squares recurrence ``q_{n+1} = c1 q_n + c2 q_{n-1}``, larger |z| first.

    Raises ValueError for fewer than four samples or a signal that vanishes.
    """
    q = np.asarray(q, float)
    if q.size < 4 or not np.any(q):
        raise ValueError(f"Prony's method needs at least 4 samples of a non-zero signal, got {q.size}")
    A = np.stack([q[1:-1], q[:-2]], axis=1)
    (c1, c2), *_ = np.linalg.lstsq(A, q[2:], rcond=None)
    z = np.roots([1.0, -c1, -c2]).astype(complex)
    z = z[np.argsort(-np.abs(z))]
    return complex(z[0]), complex(z[1])


def rate_and_frequency(z: complex, dt: float) -> tuple[float, float]:
    """Decay rate ``-log|z| / dt`` (1/s) and angular frequency ``|arg z| / dt`` (rad/s) of a root z."""
    return -math.log(abs(z)) / dt, abs(cmath.phase(z)) / dt


def amplitude_per_period(z: complex, dt: float) -> float:
    """The fraction of its amplitude a mode keeps over one period of its measured oscillation (1).

    ``|z|^(2 pi / |arg z|) = exp(-2 pi rate / freq)`` for the root z of its recurrence at step dt (s)
    (:func:`rate_and_frequency`); NaN for a real root (no oscillation, no period).
    """
    rate, freq = rate_and_frequency(z, dt)
    return math.exp(-2.0 * math.pi * rate / freq) if freq > 0 else math.nan


def undamped_claim(entries: dict, backends=BACKENDS, schemes=SCHEMES) -> dict:
    """Section 3.1's "gamma = 0: keeps oscillating", judged per scheme from the measured roots.

    ``entries``: ``{"b|undamped|scheme": dict(w0=rad/s, dt=s, z=[Re z, Im z]), ...}`` as the study's
    ``data["damping"]`` keeps them (other regimes are ignored). Returns ``kept`` {(backend, scheme): amplitude
    kept a period}, ``keeps`` {(backend, scheme): loss <= LOSS_KEPT}, ``literal`` (every scheme on every
    backend keeps it; False when none was measured), ``measured`` and ``holds_when`` (texts for the claims
    table: the loss a period of each scheme, and the schemes under which the claim holds).
    """
    kept, keeps = {}, {}
    for b in backends:
        for sc in schemes:
            e = entries.get(f"{b}|undamped|{sc}")
            if e is None:
                continue
            k = amplitude_per_period(complex(*e["z"]), e["dt"])
            kept[(b, sc)] = k
            keeps[(b, sc)] = bool(np.isfinite(k) and 1.0 - k <= LOSS_KEPT)
    steps = sorted({round(2.0 * math.pi / (entries[f"{b}|undamped|{sc}"]["w0"] * entries[f"{b}|undamped|{sc}"]["dt"]))
                    for b, sc in kept})

    def pct(k):  # the loss a period, in per cent; round-off (|loss| < 1e-9) as such
        return f"{100 * (1 - k):.3g} %" if abs(1 - k) >= 1e-9 else "< 1e-7 %"

    def loss(sc):
        return ", ".join(f"{pct(kept[(b, sc)])} ({b.upper()})" for b in backends if (b, sc) in kept)

    def name(sc):
        return SCHEME_NAMES.get(sc, sc)

    by = {sc: [b for b in backends if (b, sc) in keeps] for sc in schemes}
    good = [sc for sc in schemes if by[sc] and all(keeps[(b, sc)] for b in by[sc])]
    bad = [sc for sc in schemes if by[sc] and sc not in good]
    at = f"at {', '.join(map(str, steps))} steps a period"
    measured = (f"gamma = 0, amplitude lost a period {at}: "
                + "; ".join(f"{name(sc)} {loss(sc)}" for sc in schemes if by[sc]) if kept else
                "gamma = 0: no run measured")
    holds_when = ((f"under {' and '.join(map(name, good))}, which keeps the amplitude (loss a period "
                   f"{'; '.join(loss(sc) for sc in good)}; at most {LOSS_KEPT:.0%} counts as kept)" if good else
                   "under no scheme measured")
                  + (f"; under {' and '.join(map(name, bad))} gamma = 0 still oscillates (an under-damped response), "
                     f"but not with constant amplitude: {at} it loses "
                     + "; ".join(f"{loss(sc)} under {name(sc)}" for sc in bad)
                     + " of its amplitude a period, the scheme's numerical damping, not gamma's" if bad else ""))
    return dict(kept=kept, keeps=keeps, literal=bool(keeps) and all(keeps.values()), measured=measured,
                holds_when=holds_when)


def run_mode(backend: str, nodes: int, regime: str, scheme: str) -> dict:
    """Run the mode in one regime (a key of REGIMES) with one of SCHEMES: the modal coordinate q(t), its roots."""
    p = DAMPING
    probe = make_model(membrane(nodes), backend)
    w0, phi = lowest_mode(probe)
    zeta = REGIMES[regime]
    gamma = 2.0 * zeta * p["mu"] * w0
    model = make_model(membrane(nodes, gamma), backend)
    dt = 2.0 * math.pi / (w0 * STEPS_PER_PERIOD)
    X0 = model.initial_state()
    X0[:, 2] += p["amplitude"] * phi / np.max(np.abs(phi))
    Mz = model.mass() @ phi
    stepper = dm.TimeStepper(model, dt, scheme=scheme,
                             newton=None if scheme == "semi-implicit" else dict(rtol=1e-12, atol=0.0, test="force"))
    q = [float(Mz @ X0[:, 2])]
    result = stepper.run(X0, steps=PERIODS * STEPS_PER_PERIOD,
                         trackers=[dm.Callback(lambda s: q.append(float(Mz @ s.X[:, 2])))])
    q = np.array(q)
    z = prony(q)
    L1, L2 = p["size"]
    return dict(status=result.status, w0=w0,
                w0_continuum=math.sqrt(p["alpha"] * math.pi**2 * (L1**-2 + L2**-2) / p["mu"]), zeta=zeta,
                gamma=gamma, dt=dt, q=q, z=z, sign_changes=int(np.sum(np.diff(np.sign(q)) != 0)))


def measure(res, R: dict, s) -> list[Claim]:
    """Section 3.1: the three regimes on one mode, measured against the formula and each scheme's root."""
    rows = []
    exact, formula, regime_ok, dissipative_ok = {}, {}, {}, []
    for b in BACKENDS:
        for regime, zeta in REGIMES.items():
            for scheme in SCHEMES:
                r = R[(b, regime, scheme)]
                w0, dt = r["w0"], r["dt"]
                s_slow = mass_spring_roots(w0, zeta)[0]
                rate_f, freq_f = -s_slow.real, abs(s_slow.imag)
                rate_p, freq_p = rate_and_frequency(scheme_root(scheme, w0, zeta, dt), dt)
                rate_m, freq_m = rate_and_frequency(r["z"][0], dt)
                label = f"{b.upper()} {regime}, {scheme}"
                # the measurement against the scheme's own root: the solver's precision (Newton to 1e-12)
                exact[label] = (abs(rate_m - rate_p) <= 1e-6 * w0 and abs(freq_m - freq_p) <= 1e-6 * w0
                                and r["status"] == "finished")
                if scheme == "newmark":  # second order: within (w0 dt)^2 of the continuous formula
                    formula[label] = max(abs(rate_m - rate_f), abs(freq_m - freq_f)) <= (w0 * dt) ** 2 * w0
                oscillates = r["sign_changes"] >= 2
                regime_ok[label] = (not oscillates if zeta > 1 else oscillates) and (
                    rate_m > 1e-3 * w0 if zeta > 0 else (scheme != "newmark" or abs(rate_m) <= 1e-8 * w0))
                if zeta > 0:
                    dissipative_ok.append(regime_ok[label])
                rows.append((b.upper(), regime, zeta, scheme, w0, r["w0_continuum"], rate_f, rate_p, rate_m, freq_f,
                             freq_p, freq_m, r["sign_changes"], amplitude_per_period(r["z"][0], dt)))
    res.tables.append(Table(
        "damping", "Section 3.1: the damping regimes of one sheet mode against the mass-spring formula",
        ("backend", "regime", "zeta", "scheme", "w0 grid (rad/s)", "w0 continuum (rad/s)", "rate formula (1/s)",
         "rate scheme (1/s)", "rate measured (1/s)", "freq formula (rad/s)", "freq scheme (rad/s)",
         "freq measured (rad/s)", "sign changes of q", "amplitude kept a period (measured)"), rows,
        note=f"A {DAMPING['size'][0]:g} m x {DAMPING['size'][1]:g} m membrane pinned on its edges, frozen model "
             f"(alpha = {DAMPING['alpha']:g} N/m, beta = 0, mu = {DAMPING['mu']:g} kg/m^2; FD "
             f"{DAMPING['nodes']['fd']}x{DAMPING['nodes']['fd']} nodes, FE {DAMPING['nodes']['fe'] - 1}x"
             f"{DAMPING['nodes']['fe'] - 1} elements), started from its lowest mode shape at rest, gamma = 2 zeta mu "
             f"w0, {STEPS_PER_PERIOD} steps a period for {PERIODS} periods. 'formula': the roots of q'' + (gamma / mu) "
             "q' + w0^2 q = 0 with the grid's w0; 'scheme': the root of the scheme's recurrence for that equation; "
             "'measured': Prony's method on the modal coordinate q = phi^T M z (module docstring of "
             "validation.studies.paper.damping). Over-damped: the slower root. 'amplitude kept a period': "
             "exp(-2 pi rate / freq) of the measured root (the formula's at zeta = 0.1: "
             f"{math.exp(-2 * math.pi * 0.1 / math.sqrt(1 - 0.01)):.3f}; at zeta = 0: 1)."))
    res.check_all("section 3.1, damping: the measured roots are the scheme's roots",
                  "decay rate and frequency of the modal coordinate equal the root of the scheme's recurrence for "
                  "q'' + (gamma/mu) q' + w0^2 q = 0, within 1e-6 w0", exact)
    res.check_all("section 3.1, damping: Newmark reproduces the mass-spring formula",
                  "decay rate and frequency within (w0 dt)^2 w0 of the continuous roots (the trapezoidal rule's "
                  "second-order error; no numerical damping)", formula)
    res.check_all("section 3.1, damping: the three regimes",
                  "over-damped: q never changes sign twice; damped: it oscillates and decays (rate > 1e-3 w0); "
                  "undamped: it oscillates, and under Newmark does not decay (rate <= 1e-8 w0)", regime_ok)
    res.data["damping"] = {f"{b}|{reg}|{sc}": dict(w0=R[(b, reg, sc)]["w0"], dt=R[(b, reg, sc)]["dt"],
                                                    z=[R[(b, reg, sc)]["z"][0].real, R[(b, reg, sc)]["z"][0].imag],
                                                    sign_changes=R[(b, reg, sc)]["sign_changes"])
                           for b in BACKENDS for reg in REGIMES for sc in SCHEMES}
    und = undamped_claim(res.data["damping"])
    osc = sorted({R[(b, "undamped", sc)]["sign_changes"] for b in BACKENDS for sc in SCHEMES})
    res.findings.append(
        f"Section 3.1, {und['measured']} (the paper's step predicts 1 - (1 + (w0 dt)^2)^(-pi / (w0 dt)) = "
        f"{1 - (1 + (2 * math.pi / STEPS_PER_PERIOD) ** 2) ** (-STEPS_PER_PERIOD / 2):.1%} over {STEPS_PER_PERIOD} "
        f"steps). Every scheme oscillates ({' to '.join(map(str, sorted({osc[0], osc[-1]})))} sign changes of q in "
        f"{PERIODS} periods); "
        f"'keeps oscillating' (losing at most {LOSS_KEPT:.0%} a period) holds {und['holds_when']}.")
    checks = checks_of(res, "section 3.1, damping")
    return [Claim("gamma large: over-damped; mu larger: damped oscillation", "3.1",
                  "one membrane mode on both backends, three schemes: roots measured against the mass-spring "
                  "formula (table 'damping')", literal=bool(dissipative_ok) and all(dissipative_ok), checks=checks),
            Claim("gamma = 0: keeps oscillating", "3.1", und["measured"] + " (table 'damping')",
                  literal=und["literal"], checks=checks, holds_when=und["holds_when"])]
