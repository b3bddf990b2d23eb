#!/usr/bin/env python3
"""Tests of the three-mesh estimate of bench/rolling_convergence.py (observed order, Richardson's
extrapolation and grid convergence index, and the fallbacks), against the worked example of Celik et
al., J. Fluids Eng. 130 (2008) 078001, Table 1, and against exact power laws."""
import os
import sys
import unittest

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "bench"))
from rolling_convergence import richardson  # noqa: E402


class Richardson(unittest.TestCase):
    def test_celik_worked_example(self):
        # Celik et al. 2008, Table 1, first column: phi_1..3 = 6.063, 5.972, 5.863 (fine to coarse),
        # r21 = 1.5, r32 = 1.333; published p = 1.53, phi_ext21 = 6.1685, GCI_fine21 = 2.17 %.
        fit = richardson(5.863, 5.972, 6.063, 1.5, 1.333)
        self.assertEqual(fit["how"], "Richardson")
        self.assertAlmostEqual(fit["order"], 1.53, delta=0.01)
        self.assertAlmostEqual(fit["value"], 6.1685, delta=5e-4)
        self.assertAlmostEqual(100 * fit["uncertainty"], 2.17, delta=0.02)

    def test_recovers_an_exact_power_law_on_unequal_ratios(self):
        for order in (0.5, 1.0, 1.5, 2.0):
            phi = [0.95 - 0.4 * (1.0 / n) ** order for n in (68, 136, 204)]
            fit = richardson(*phi, 1.5, 2.0)
            self.assertEqual(fit["how"], "Richardson")
            self.assertAlmostEqual(fit["order"], order, delta=1e-6)
            self.assertAlmostEqual(fit["value"], 0.95, delta=1e-10)

    def test_an_order_far_from_the_formal_one_falls_back_to_a_safety_factor_3(self):
        # Roache: with an unreasonable observed order, the formal order (1) and F_s = 3 on the two finest.
        phi = [0.95 - 0.4 * (1.0 / n) ** 3.7 for n in (68, 136, 204)]
        fit = richardson(*phi, 1.5, 2.0)
        self.assertEqual(fit["how"], "finest, F_s 3")
        self.assertAlmostEqual(fit["order"], 3.7, delta=1e-4)
        self.assertEqual(fit["value"], phi[2])
        self.assertAlmostEqual(fit["uncertainty"], 3.0 * (phi[2] - phi[1]) / phi[2] / 0.5, delta=1e-15)
        # Differences whose ratio is below ln r32 / ln r21 = 1.71 have no order p > 0.
        self.assertIsNone(richardson(0.9510, 0.9500, 0.9490, 1.5, 2.0)["order"])

    def test_oscillatory_convergence_takes_half_the_range(self):
        fit = richardson(0.67832, 0.66751, 0.66874, 1.5, 2.0)
        self.assertEqual(fit["how"], "oscillatory")
        self.assertEqual(fit["value"], 0.66874)
        self.assertAlmostEqual(fit["uncertainty"], 0.5 * (0.67832 - 0.66751) / 0.66874, delta=1e-15)


if __name__ == "__main__":
    unittest.main()
