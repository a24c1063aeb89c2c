"""Identifying a ur5's dynamics from noisy torques: an excitation trajectory, weighted least squares on the
base parameters, the physically consistent fit, and the torques of a second trajectory predicted.

The robot follows a finite Fourier series per joint within ±LIMIT rad and ±SPEED rad/s, optimised for the
condition number of the base regressor (`eg.excite`); the torques it needs there are its inverse
dynamics (the C backend) plus viscous and Coulomb friction, measured with Gaussian noise of NOISE times
each joint's RMS torque. `eg.identify` recovers the base parameters with their standard deviations;
`eg.identify_consistent` the full parameters with every link's pseudo-inertia positive semidefinite.
A second, random Fourier trajectory checks the prediction on data the fit has not seen.

Run: python examples/identification.py [output folder]   (writes identification.png)"""
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import eomgen as eg
from eomgen.identification import numeric_regressor, random_fourier

LIMIT, SPEED, PERIOD = 1.5, 1.5, 10.0  # rad, rad/s, s
NOISE, SAMPLES = 0.02, 400  # the torques' noise (fraction of each joint's RMS), samples per period
FRICTION = {"Fv": 0.3, "Fc": 0.6}  # N m s/rad, N m: the same on every joint


@dataclass
class Result:
    truth: np.ndarray  # π of the model and FRICTION
    excitation: eg.identification.Excitation
    fit: eg.identification.Identification
    consistent: eg.identification.ConsistentIdentification
    measured: tuple  # (t, τ measured, τ predicted) on the excitation trajectory
    held_out: tuple  # the same on the second trajectory


def setup():
    """The ur5, its regressor with viscous and Coulomb friction (C), and the true parameters."""
    system = eg.robots.load("ur5")
    r = eg.regressor(system, friction=("viscous", "coulomb"))
    Y = numeric_regressor(r, backend="c")
    truth = Y.pi
    for k, name in enumerate(r.names):
        truth[k] = FRICTION.get(name.split("_")[0], truth[k])
    return system, Y, truth


def measure(Y, truth: np.ndarray, fourier, rng: np.random.Generator) -> tuple:
    """(t, q, u, u̇, τ measured) over one period: τ = Y π (the inverse dynamics and friction) + noise."""
    t = np.linspace(0.0, PERIOD, SAMPLES, endpoint=False)
    q, u, ud = fourier(t)
    tau = Y(q, u, ud) @ truth
    return t, q, u, ud, tau + NOISE * np.sqrt((tau**2).mean(axis=0)) * rng.standard_normal(tau.shape)


def run(seed: int = 0, time_limit: float = 20.0) -> Result:
    system, Y, truth = setup()
    rng = np.random.default_rng(seed)
    lower, upper, speed = -LIMIT * np.ones(6), LIMIT * np.ones(6), SPEED * np.ones(6)
    excitation = eg.excite(Y, lower, upper, speed, harmonics=4, period=PERIOD, samples=60, restarts=2,
                           time_limit=time_limit, rng=rng)
    t, q, u, ud, tau = measure(Y, truth, excitation.fourier, rng)
    fit = eg.identify(Y, q, u, ud, tau, base=excitation.base)
    consistent = eg.identify_consistent(Y, q, u, ud, tau, base=excitation.base)
    times = np.linspace(0.0, PERIOD, 60, endpoint=False)
    other = random_fourier(rng, lower, upper, speed, 4, 2 * np.pi / PERIOD, times)
    t2, q2, u2, ud2, tau2 = measure(Y, truth, other, rng)
    return Result(truth, excitation, fit, consistent, (t, tau, fit.predict(q, u, ud)),
                  (t2, tau2, fit.predict(q2, u2, ud2)))


def report(result: Result) -> None:
    fit, base = result.fit, result.fit.base
    error = (fit.beta - base.of(result.truth)) / fit.std
    print(f"excitation: cond(Y_b) {result.excitation.condition:.1f} (best random start "
          f"{result.excitation.start:.1f}); {base.rank} base parameters of {len(base.parameters)}")
    print(f"least squares: cond {fit.condition:.1f}; |β̂ − β| ≤ 3σ for {np.mean(np.abs(error) <= 3):.0%} "
          f"of them; torque RMS error per joint {np.round(fit.rms, 3)} N m")
    held_t, held_tau, held_hat = result.held_out
    print(f"second trajectory: prediction RMS error {np.round(np.sqrt(((held_tau - held_hat)**2).mean(0)), 3)}"
          f" N m (noise {NOISE:.0%} of each joint's RMS torque)")
    print(f"consistent fit: smallest pseudo-inertia eigenvalue {result.consistent.eigenvalues.min():.2e}; "
          f"torque RMS {np.round(result.consistent.rms, 3)} N m")


def figure(result: Result, path: Path | None = None):
    """Measured and predicted torques of three joints, on the excitation and the second trajectory."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 2, figsize=(10, 7), sharex=True)
    for column, (title, (t, tau, hat)) in enumerate((("excitation (fitted)", result.measured),
                                                     ("second trajectory (predicted)", result.held_out))):
        for row, joint in enumerate((0, 1, 2)):
            ax = axes[row, column]
            ax.plot(t, tau[:, joint], ".", ms=2, color="0.6", label="measured")
            ax.plot(t, hat[:, joint], "-", lw=1.2, color="C0", label="Y_b β̂")
            ax.set_ylabel(f"τ{joint + 1} (N m)")
        axes[0, column].set_title(title)
        axes[-1, column].set_xlabel("t (s)")
    axes[0, 0].legend(loc="upper right")
    fig.tight_layout()
    if path is not None:
        fig.savefig(path, dpi=110)
    return fig


def main(folder: Path) -> None:
    eg.quiet()
    result = run()
    report(result)
    figure(result, folder / "identification.png")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("."))
