#!/usr/bin/env python3
"""Golden values for tests/fiber/test_fiber.c, worked independently of the
C code from the papers' formulas in double precision (mpmath for the Bessel
function and the hyperbolic sine, no log-form shortcut):
  M_p: d'Eon 2011 eq. 7, csch(1/v)/(2v) exp(-sin_i sin_o/v) I0(cos_i cos_o/v)
  N_p: Chiang 2016 eq. 10-11, logistic trimmed to [-pi, pi]
  A_p: d'Eon 2011 eq. 12-14, Fresnel at cos(theta_o) cos(gamma_o),
       T = exp(-sigma_a 2 cos(gamma_t) / cos(theta_t)), Bravais eta'
  v, s: Chiang 2016 eq. 7-8; lobes v, v/4, 4v, 4v; tilt as Cycles rotates
       theta_o (R +2a, TT -a, TRT -4a), Cycles' direction
  sigma_a: Cycles' melanin mode.
Prints the C initialisers the test pastes. usage: python3 test_fiber_golden.py"""
import math
import mpmath

def sigma_melanin(m, r):
    q = -math.log(max(1 - m, 1e-4))
    eu, ph = q * (1 - r), q * r
    return [eu * a + ph * b for a, b in zip((0.506, 0.841, 1.653), (0.343, 0.733, 1.924))]

def mp(ti, to, v):
    return float(mpmath.besseli(0, math.cos(ti) * math.cos(to) / v) *
                 mpmath.exp(-math.sin(ti) * math.sin(to) / v) /
                 (2 * v * mpmath.sinh(1 / v)))

def fresnel(c, eta):
    s2 = 1 - c * c
    ct = math.sqrt(1 - s2 / eta ** 2)
    rpar = (eta * c - ct) / (eta * c + ct)
    rper = (c - eta * ct) / (c + eta * ct)
    return 0.5 * (rpar ** 2 + rper ** 2)

def logistic(x, s):
    return math.exp(-abs(x) / s) / (s * (1 + math.exp(-abs(x) / s)) ** 2)

def trimmed(x, s):
    cdf = lambda y: 1 / (1 + math.exp(-y / s))
    return logistic(x, s) / (cdf(math.pi) - cdf(-math.pi))

def bcsdf(wo, wi, h, sig, bm, bn, alpha, eta):
    v0 = (0.726 * bm + 0.812 * bm ** 2 + 3.7 * bm ** 20) ** 2
    vs = [v0, v0 / 4, 4 * v0, 4 * v0]
    s = math.sqrt(math.pi / 8) * (0.265 * bn + 1.194 * bn ** 2 + 5.372 * bn ** 22)
    to, ti = math.asin(wo[0]), math.asin(wi[0])
    po, pi_ = math.atan2(wo[2], wo[1]), math.atan2(wi[2], wi[1])
    go = math.asin(h)
    etap = math.sqrt(eta ** 2 - math.sin(to) ** 2) / math.cos(to)
    gt = math.asin(h / etap)
    tt = math.asin(math.sin(to) / eta)
    f = fresnel(math.cos(to) * math.cos(go), eta)
    shifts = [2 * alpha, -alpha, -4 * alpha, 0]
    out = []
    for c in range(3):
        T = math.exp(-sig[c] * 2 * math.cos(gt) / math.cos(tt))
        a = [f, (1 - f) ** 2 * T]
        a.append(a[1] * T * f)
        a.append(a[2] * T * f / (1 - T * f))
        tot = 0
        for p in range(4):
            m = mp(ti, to + shifts[p], vs[p])
            if p < 3:
                d = pi_ - po - (2 * p * gt - 2 * go + p * math.pi)
                d = (d + math.pi) % (2 * math.pi) - math.pi
                n = trimmed(d, s)
            else:
                n = 1 / (2 * math.pi)
            tot += m * a[p] * n
        out.append(tot)
    return out

def unit(th, ph):
    return (math.sin(th), math.cos(th) * math.cos(ph), math.cos(th) * math.sin(ph))

cases = [  # theta_o, phi_o, theta_i, phi_i, h, melanin, redness, bm, bn, alpha(deg)
    (0.3, 1.5708, -0.25, 1.2, 0.2, 0.6, 0.0, 0.3, 0.3, 2.0),
    (-0.5, 0.4, 0.45, 3.0, -0.7, 0.2, 0.5, 0.25, 0.4, 2.0),
    (0.1, 1.0, 0.2, -2.5, 0.0, 0.0, 0.0, 0.5, 0.6, 0.0),
    (0.8, -1.2, -0.7, 2.1, 0.9, 0.9, 0.2, 0.15, 0.2, 3.0),
]
for c in cases:
    to, po, ti, pi_, h, m, r, bm, bn, al = c
    out = bcsdf(unit(to, po), unit(ti, pi_), h, sigma_melanin(m, r), bm, bn,
                math.radians(al), 1.55)
    print('{%gf, %gf, %gf, %gf, %gf, %gf, %gf, %gf, %gf, %gf, {%.7gf, %.7gf, %.7gf}},' % (c + tuple(out)))
