"""The radial map of ``benchmarks/radial_ab.py``'s prototype: a homeomorphism of R^2 onto the
open box that keeps the inner box and the directions from the centre."""

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import radial_ab

LO, HI = radial_ab.BOX


def test_the_radial_map_is_the_identity_inside_and_inverts_its_inverse():
    rng = np.random.default_rng(3)
    inner = rng.uniform(LO + 1.25, HI - 1.25, (500, 2))  # the inner box: BAND 1/8 of 10
    assert np.allclose(radial_ab._radial(inner, False), inner, rtol=0, atol=1e-13)
    assert np.allclose(radial_ab._radial(inner, True), inner, rtol=0, atol=1e-13)
    x = rng.uniform(LO + 1e-6, HI - 1e-6, (2000, 2))
    assert np.allclose(radial_ab._radial(radial_ab._radial(x, True), False), x, rtol=0,
                       atol=1e-11)


def test_the_radial_map_sends_far_points_into_the_open_box_along_their_direction():
    c = (LO + HI) / 2
    for angle in np.linspace(0.0, 2 * np.pi, 37):
        v = np.array([np.cos(angle), np.sin(angle)])
        far = c + np.outer([10.0, 100.0, 1e4, 1e8], v)
        y = radial_ab._radial(far, False)
        assert ((y > LO) & (y < HI)).all()
        w = (y - c) / np.linalg.norm(y - c, axis=1, keepdims=True)  # the same direction
        assert np.allclose(w, v, atol=1e-12)
        r = np.abs(y - c).max(axis=1)  # further out in R^2, nearer the wall, in order
        assert (np.diff(r) > 0).all()
