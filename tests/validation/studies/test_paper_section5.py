"""Study ``paper``, sections 3.1 and 5: the fold counter, the flag's phase estimator, the damping regimes.

- the fold counter counts the folds of synthetic rows (sines with known half-waves), ignores wiggles below its
  hysteresis and trends, never counts an end of the row, and gives the widths;
- the phase estimator finds the phase change, speed and direction of a synthetic travelling wave, and no
  change on a flag that flaps in phase;
- one membrane mode, run in the three regimes of section 3.1, has the roots of the mass-spring formula under
  Newmark and the numerical damping its recurrence predicts under the paper's step;
- a shipped scene's run records what the measures need;
- the README's media: a GIF with every frame and a PNG still; bad arguments refused in one line.
"""

import io
import math

import numpy as np
import pytest

from deformable.scenes import FoldNoise
from validation.studies.paper import damping, flag, folds
from validation.studies.paper.cases import Case, fields, run_case

L = 1.0
A = np.linspace(0.0, L, 129)


@pytest.mark.parametrize("half_waves", [1, 2, 3, 5, 8, 13])
def test_a_sine_with_k_half_waves_has_k_folds_of_width_L_over_k(half_waves):
    y = 0.03 * np.sin(half_waves * math.pi * A / L)
    f = folds.row_folds(A, y)
    assert f.count == half_waves
    if half_waves > 1:
        assert abs(f.width - L / half_waves) <= A[1], (f.width, L / half_waves)
        assert abs(f.narrowest - L / half_waves) <= A[1]


def test_wiggles_below_the_hysteresis_and_trends_make_no_fold():
    base = 0.04 * np.sin(4 * math.pi * A / L)  # four folds
    wiggle = 0.3 * folds.DELTA_MIN * np.sin(60 * math.pi * A / L)  # far below delta: not folds
    trend = 0.02 * A / L  # a tilted row: no extra extremum
    assert folds.row_folds(A, base + wiggle + trend).count == 4
    for seed in range(1, 51):  # the curtain's seeded start (1 mm RMS) has no fold, whatever the seed
        start = FoldNoise(L, 1e-3, seed).r(A, 0.0 * A)[:, 1]
        assert folds.row_folds(A, start).count == 0, seed
    # a dip deeper than the hysteresis splits the first ridge: two extra extrema, one narrow fold
    dip = -0.03 * np.exp(-(((A - 0.125) / 0.015) ** 2))
    split = folds.row_folds(A, base + dip)
    assert split.count == 6 and split.narrowest < 0.05
    assert abs(split.narrowest_at - 0.125) < 0.03  # and says where it is


def test_an_end_of_the_row_is_never_a_fold():
    assert folds.row_folds(A, 0.03 * np.cos(3 * math.pi * A / L)).count == 2  # ends are extrema of cos
    assert folds.row_folds(A, A**2).count == 0
    with pytest.raises(ValueError, match="delta must be positive"):
        folds.extrema(A, 0.0)


def test_a_snapshot_takes_medians_over_rows_and_a_run_over_its_late_snapshots():
    rows = np.array([0.03 * np.sin(k * math.pi * A / L) for k in (4, 5, 6)])
    snap = folds.snapshot_folds(A, rows)
    assert snap["count"] == 5 and snap["counts"] == [4, 5, 6]
    assert abs(snap["narrowest"] - L / 6) <= A[1]
    series = folds.fold_series(A, [0.0, 1.6, 1.8, 2.0], [rows * 0.0, rows, rows[::-1], rows])
    late = folds.late_folds(series, 2.0, late=0.4)
    assert late["snapshots"] == 3 and late["count"] == 5
    assert series[0]["count"] == 0 and math.isnan(series[0]["width"])


def test_power_fit_recovers_an_exponent_and_prefactor():
    x = np.array([1e-5, 1e-4, 1e-3])
    p, c = folds.power_fit(x, 0.3 * x**-0.25)
    assert abs(p + 0.25) < 1e-12 and abs(c / 0.3 - 1) < 1e-10
    assert all(math.isnan(v) for v in folds.power_fit([1.0], [2.0]))


@pytest.mark.parametrize("k, direction", [(-2.8, "towards the pole"), (4.0, "towards the tip")])
def test_the_phase_of_a_travelling_wave_gives_its_speed_and_direction(k, direction):
    f = 4.0
    w = 2 * math.pi * f
    a = np.linspace(0.0, 1.2, 49)
    t = np.arange(1.0, 2.0 + 1e-9, 5e-3)
    envelope = np.sin(math.pi * a / 2.4)  # zero at the pole, like a pinned edge
    y = envelope * np.cos(w * t[:, None] - k * a) + 0.02 + 0.05 * t[:, None]  # plus an offset and a drift
    p = flag.phase_along(a, t, y, f)
    kept = a[np.isfinite(p.phase)]
    assert p.direction == direction
    assert abs(p.speed - w / abs(k)) <= 1e-6 * w / abs(k)
    assert abs(p.change - k * (kept[-1] - kept[0])) <= 1e-6
    flap = flag.phase_along(a, t, envelope * np.cos(w * t[:, None]), f)  # in phase everywhere: no wave
    assert abs(flap.change) < 1e-9 and flap.speed > 1e6


def test_the_analysis_window_holds_whole_periods_after_the_ramp():
    assert flag.window(2.0, 0.5, 4.0) == (1.0, 2.0)
    lo, hi = flag.window(2.1, 0.5, 3.0)
    assert hi == 2.1 and abs((hi - lo) * 3.0 - round((hi - lo) * 3.0)) < 1e-9 and lo >= 1.0
    with pytest.raises(ValueError, match="no whole period"):
        flag.window(0.8, 0.5, 4.0)


def test_prony_recovers_the_roots_of_a_damped_oscillation():
    z = 0.99 * np.exp(0.2j)
    n = np.arange(40)
    q = np.real(1.5 * z**n * np.exp(0.3j))
    found = damping.prony(q)
    assert abs(found[0] - z) < 1e-10 or abs(found[0] - np.conj(z)) < 1e-10
    with pytest.raises(ValueError, match="at least 4 samples"):
        damping.prony(np.zeros(10))


@pytest.mark.parametrize("regime", list(damping.REGIMES))
def test_one_sheet_mode_follows_the_mass_spring_formula_under_newmark(regime):
    r = damping.run_mode("fd", 5, regime, "newmark")
    zeta, w0, dt = damping.REGIMES[regime], r["w0"], r["dt"]
    s = damping.mass_spring_roots(w0, zeta)[0]
    rate, freq = damping.rate_and_frequency(r["z"][0], dt)
    assert r["status"] == "finished"
    assert abs(rate + s.real) <= (w0 * dt) ** 2 * w0 and abs(freq - abs(s.imag)) <= (w0 * dt) ** 2 * w0
    assert (r["sign_changes"] == 0) if zeta > 1 else (r["sign_changes"] >= 2 * damping.PERIODS - 1)
    if zeta == 0:
        assert abs(rate) <= 1e-8 * w0  # the trapezoidal rule does not damp


def test_the_papers_step_damps_an_undamped_mode_as_its_recurrence_predicts():
    r = damping.run_mode("fd", 5, "undamped", "semi-implicit")
    w0, dt = r["w0"], r["dt"]
    rate, _ = damping.rate_and_frequency(r["z"][0], dt)
    predicted = math.log(1 + (w0 * dt) ** 2) / (2 * dt)  # |z| = (1 + w^2 dt^2)^(-1/2)
    assert abs(rate / predicted - 1) <= 1e-6, (rate, predicted)
    assert rate > 0.05 * w0 * (w0 * dt)  # numerical damping about w0^2 dt / 2: not "keeps oscillating"


def test_a_shipped_scene_run_records_the_fold_rows_and_the_flag_line():
    curtain = run_case(Case("scene", "curtain", "fd", 6, fields(force_model="variational"), t_end=0.2,
                            times=(0.0, 0.2), every=20))
    assert curtain["status"] == "finished"
    assert curtain["rows"].shape == (3, len(folds.ROWS), folds.SAMPLES * 5 + 1)  # t = 0, 0.1, 0.2
    assert np.allclose(curtain["rows_t"], [0.0, 0.1, 0.2]) and sorted(curtain["renders"]) == [0.0, 0.2]
    assert len(curtain["frames"]) == 3  # every 20 steps of 5 ms, from t = 0
    flag_run = run_case(Case("scene", "flag", "fd", 6, fields(force_model="variational"), t_end=0.05))
    assert flag_run["line"].shape == (11, folds.SAMPLES * 5 + 1) and flag_run["rows"].size == 0


def _fake_run(frames=4):
    """A run as media.scene_run records it: a curtain-sized sheet that bulges more each frame."""
    a1, a2 = np.meshgrid(np.linspace(0.0, 1.0, 9), np.linspace(0.0, 1.2, 11), indexing="ij")
    pts = [(0.1 * k, np.stack([a1, 0.02 * k * np.sin(3 * math.pi * a1), a2], axis=-1)) for k in range(frames)]
    return dict(status="finished", t=0.1 * (frames - 1), steps=frames - 1, wall=0.0, frames=pts,
                renders={pts[-1][0]: pts[-1][1]})


def test_media_makes_a_gif_with_every_frame_and_a_png_still():
    from PIL import Image

    from validation.studies.paper import media

    gif, png = media.scene_media("curtain", _fake_run(3), 9)
    anim = Image.open(io.BytesIO(gif))
    assert anim.format == "GIF" and anim.n_frames == 3
    assert Image.open(io.BytesIO(png)).format == "PNG"
    first = np.asarray(anim.convert("RGB"))
    anim.seek(2)
    assert np.any(np.asarray(anim.convert("RGB")) != first)  # the frames differ
    assert len(gif) < 1e6


def _flag_run(case):
    """A flag run as run_case records it: a frame every ``case.every`` steps of the scene's dt from t = 0."""
    from deformable import scenes

    cfg = scenes.config("flag")
    dt = cfg.dt
    t = np.arange(0, int(round(case.t_end / dt)) + 1, case.every) * dt
    a1, a2 = np.meshgrid(np.linspace(0.0, 1.2, 5), np.linspace(0.0, 0.8, 4), indexing="ij")
    frames = [(tk, np.stack([a1, 0.05 * np.sin(2 * math.pi * (cfg.frequency * tk - a1)), a2], axis=-1)) for tk in t]
    return dict(status="finished", t=case.t_end, steps=int(round(case.t_end / dt)), wall=0.0, frames=frames,
                renders={frames[-1][0]: frames[-1][1]})


@pytest.mark.parametrize("frequency", [None, 2.0, 11.0])
def test_the_flags_animation_has_at_least_12_frames_a_period_late_in_its_run(frequency, monkeypatch):
    """The flag swings at 6 Hz: over its whole run 31 frames sample a period 2.6 times and show no travelling wave;
    its animation is its last periods at 12 frames a period or more, and its still one period's phases."""
    from deformable import scenes
    from validation.studies.paper import media

    cfg = scenes.config("flag") if frequency is None else scenes.config("flag", frequency=frequency)
    monkeypatch.setattr(media.scenes, "config", lambda name, **kw: cfg)
    monkeypatch.setattr(media, "run_case", _flag_run)
    run = media.scene_run("flag", 5, frames=30)
    t = np.array([f[0] for f in run["frames"]])
    period = 1.0 / cfg.frequency
    assert period / np.diff(t).max() >= media.FLAG_FRAMES_A_PERIOD >= 12
    assert abs(t[-1] - cfg.t_end) < 1e-9 and cfg.t_end - t[0] >= media.FLAG_PERIODS * period - np.diff(t).max()
    assert t[0] >= cfg.t_end - media.FLAG_PERIODS * period - 1e-9  # a window late in the run, not all of it
    phases = [f[0] for f in media.phase_frames(run["frames"], cfg.frequency, cfg.t_end)]
    assert len(phases) == media.FLAG_PHASES and np.all(np.diff(phases) > 0) and phases[-1] - phases[0] < period
    spread = np.diff(phases) * cfg.frequency * media.FLAG_PHASES  # each step about 1 / FLAG_PHASES of a period
    assert np.all(np.abs(spread - 1) < 0.5)


def test_a_flag_step_too_long_for_12_frames_a_period_is_refused():
    from deformable import scenes
    from validation.studies.paper import media

    cfg = scenes.config("flag", frequency=20.0)  # 10 steps of 5 ms a period
    with pytest.raises(ValueError, match="too long for 12 frames a period"):
        media.flag_sampling(cfg, cfg.dt)
    every, t_from = media.flag_sampling(scenes.config("flag"), 5e-3)
    assert every == 2 and abs(t_from - (2.0 - 2 / 6.0)) < 1e-12  # 16.7 frames a period over the last 2


def test_a_floor_is_drawn_only_around_the_sheet():
    from deformable.contact.obstacles import HalfSpace
    from validation.studies.paper.pictures import floor_patch

    pts = np.array([[0.1, 0.0, 0.6], [0.4, 0.04, 0.0]])
    patch = floor_patch(HalfSpace(), pts, margin=0.1)
    lo, hi = np.asarray(patch.points).min(axis=0), np.asarray(patch.points).max(axis=0)
    assert np.allclose(lo, [0.07, -0.03, 0.0]) and np.allclose(hi, [0.43, 0.07, 0.0])


@pytest.mark.parametrize("argv, message", [(["--nodes", "2"], "--nodes must be a whole number >= 3"),
                                           (["--frames", "x"], "--frames must be a whole number >= 1"),
                                           (["curtian"], "unknown scene 'curtian'"),
                                           (["--out", "missing"], "is not a folder")])
def test_media_refuses_bad_input_in_one_line_and_writes_nothing(argv, message, tmp_path, monkeypatch, capsys):
    from validation.studies.paper import media

    monkeypatch.chdir(tmp_path)
    if "--out" not in argv:
        argv = argv + ["--out", str(tmp_path)]
    assert media.main(argv) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []


def test_a_flag_run_that_stopped_early_has_no_phase_and_does_not_stop_the_report():
    a = np.linspace(0.0, 1.2, 9)
    t = np.arange(0.0, 0.065, 5e-3)
    stopped = dict(status="diverged", t=0.065, line_t=t, line=np.zeros((t.size, a.size)), a=a,
                   config=dict(ramp=0.5, frequency=4.0))
    assert flag.run_phase(stopped, 2.0) is None
    t = np.arange(0.0, 2.0 + 1e-9, 5e-3)
    done = dict(stopped, status="finished", t=2.0, line_t=t,
                line=np.sin(math.pi * a / 2.4) * np.cos(8 * math.pi * t[:, None] + 2.0 * a))
    assert abs(flag.run_phase(done, 2.0).change + 2.0 * (a[-1] - a[1])) < 1e-6  # the point at the pole is left out
