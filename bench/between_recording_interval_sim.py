#!/usr/bin/python3
"""Coverage of the between-recording part of the calibration interval, in its idealised model.

R recordings each give a mean energy loss m_r ~ N(mu, tau_b^2 + s^2), s^2 the within-recording
variance of the mean (per-impact scatter over the impacts used, and timing), known precisely
because the per-impact scatter is estimated from every measured impact. Two intervals for mu,
each at 95 %:

- "moments", what calibrate does (calibrate/src/fit_uncertainty.cc, VarianceAt): tau_b^2 =
  max(0, MS_b - s^2) with MS_b the recordings' sample variance; where positive the variance of the
  mean is MS_b / R with Student's t at R - 1 dof (Satterthwaite's dof of that combination in a
  balanced design), else s^2 / R with the normal quantile;
- "jeffreys": tau_b^2 integrated over its restricted-likelihood posterior under the Jeffreys
  prior p(tau_b^2) ~ 1 / (tau_b^2 + s^2) (Bodnar et al. 2017), a mixture of normals.

It prints coverage and mean half-width per R and tau_b^2 / s^2. Deterministic (--seed). Needs
numpy and scipy (Debian python3-numpy, python3-scipy).

    bench/between_recording_interval_sim.py [--cases 4000] [--seed 1]
"""
import argparse

import numpy as np
from scipy import stats


def coverage(rng, recordings, between_ratio, cases):
    within = 1.0
    means = rng.normal(0.0, np.sqrt(between_ratio * within + within), (cases, recordings))
    grand = means.mean(axis=1)
    ms = means.var(axis=1, ddof=1)
    # moments
    positive = ms > within
    half_moments = np.where(positive,
                            stats.t.ppf(0.975, recordings - 1) * np.sqrt(ms / recordings),
                            stats.norm.ppf(0.975) * np.sqrt(within / recordings))
    # jeffreys: tau_b^2 on a grid (0 and log-spaced), trapezoid weights
    grid = np.concatenate([[0.0], np.exp(np.linspace(np.log(1e-4), np.log(1e3), 200))]) * within
    step = np.gradient(grid)
    v = grid + within
    log_post = (-(recordings - 1) / 2 * np.log(v)[None, :]
                - (recordings - 1) * ms[:, None] / (2 * v[None, :]) - np.log(v)[None, :])
    weight = np.exp(log_post - log_post.max(axis=1, keepdims=True)) * step[None, :]
    weight /= weight.sum(axis=1, keepdims=True)
    sd = np.sqrt(v / recordings)
    low = np.zeros(cases)
    high = np.full(cases, 50.0 * np.sqrt(v.max() / recordings))
    for _ in range(60):
        middle = 0.5 * (low + high)
        inside = (weight * (2 * stats.norm.cdf(middle[:, None] / sd[None, :]) - 1)).sum(axis=1)
        low = np.where(inside < 0.95, middle, low)
        high = np.where(inside < 0.95, high, middle)
    half_jeffreys = 0.5 * (low + high)
    return (np.mean(np.abs(grand) <= half_moments), np.mean(np.abs(grand) <= half_jeffreys),
            half_moments.mean(), half_jeffreys.mean())


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--cases", type=int, default=4000)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    print("recordings  tau_b^2/s^2  coverage moments  jeffreys  half-width moments  jeffreys")
    for recordings in (3, 5):
        for ratio in (0.0, 0.25, 1.0, 4.0):
            c_m, c_j, w_m, w_j = coverage(rng, recordings, ratio, args.cases)
            print(f"{recordings:10d}  {ratio:11.2f}  {100 * c_m:15.1f} %  {100 * c_j:6.1f} %"
                  f"  {w_m:18.3f}  {w_j:8.3f}")


if __name__ == "__main__":
    main()
