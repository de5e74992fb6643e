#!/usr/bin/env python3
"""The coefficients of `src/math/elementary.rs`'s atan: atan u = u + u z P(z)/Q(z), z = u², on
|u| <= tan(pi/8), P of degree 3, Q of degree 4 with Q(0) = 1, minimax in atan's relative error.

Remez' exchange for rational functions in 50-digit decimal arithmetic (the standard library only): at m + n + 2
reference points the weighted error (P/Q - R) w alternates in sign with one magnitude E, where R(z) = (atan u -
u)/(u z) = sum_k (-1)^(k+1) z^k/(2k+3) and w = z/(1 + z R) makes it atan's relative error; the system is made
linear by the previous iteration's Q on the E term, and the references move to the error's extrema on a
3000-point Chebyshev grid. Prints the levelled error and the coefficients as Rust wants them.

    python3 scripts/atan_coefficients.py            # the shipped 3/4
    python3 scripts/atan_coefficients.py 3 3        # another degree: 3.9e-16, for comparison
"""
import math
import sys
from decimal import Decimal as D, getcontext

getcontext().prec = 50


def r_of(z):
    """(atan u - u)/(u z), z = u^2, by its series (|z| <= 0.18: 40 digits within about 60 terms)."""
    s, t, k = D(0), D(-1), 0
    while True:
        term = t / (2 * k + 3)
        s += term
        if abs(term) < D(10) ** -45:
            return s
        t *= -z
        k += 1


def poly(c, z):
    s = D(0)
    for co in reversed(c):
        s = s * z + co
    return s


def solve(a, b):
    n = len(b)
    m = [row[:] + [bb] for row, bb in zip(a, b)]
    for i in range(n):
        p = max(range(i, n), key=lambda r: abs(m[r][i]))
        m[i], m[p] = m[p], m[i]
        for r in range(i + 1, n):
            f = m[r][i] / m[i][i]
            m[r] = [x - f * y for x, y in zip(m[r], m[i])]
    x = [D(0)] * n
    for i in reversed(range(n)):
        x[i] = (m[i][n] - sum(m[i][j] * x[j] for j in range(i + 1, n))) / m[i][i]
    return x


def remez(m, n, zmax, iterations=25):
    count = m + n + 2
    grid = [zmax * (1 - D(math.cos(math.pi * (i + 0.5) / 3000))) / 2 for i in range(3000)]
    r_grid = [r_of(z) for z in grid]
    ref = [zmax * (1 - D(math.cos(math.pi * i / (count - 1)))) / 2 for i in range(count)]
    ref[0] = zmax * D("1e-6")
    q_prev = [D(1)] + [D(0)] * n
    for _ in range(iterations):
        for _ in range(3):
            a, b = [], []
            for i, z in enumerate(ref):
                r = r_of(z)
                w = z / (1 + z * r)
                a.append(
                    [z**j for j in range(m + 1)]
                    + [-r * z**j for j in range(1, n + 1)]
                    + [-((-1) ** i) * poly(q_prev, z) / w]
                )
                b.append(r)
            x = solve(a, b)
            p, q, levelled = x[: m + 1], [D(1)] + x[m + 1 : m + 1 + n], x[-1]
            q_prev = q
        err = [(poly(p, z) / poly(q, z) - r) * z / (1 + z * r) for z, r in zip(grid, r_grid)]
        peaks = [
            i
            for i in range(len(grid))
            if (i == 0 or abs(err[i]) >= abs(err[i - 1])) and (i == len(grid) - 1 or abs(err[i]) >= abs(err[i + 1]))
        ]
        alternating = []
        for i in peaks:
            if alternating and (err[i] > 0) == (err[alternating[-1]] > 0):
                if abs(err[i]) > abs(err[alternating[-1]]):
                    alternating[-1] = i
            else:
                alternating.append(i)
        while len(alternating) > count:
            alternating.pop(0 if abs(err[alternating[0]]) < abs(err[alternating[-1]]) else -1)
        if len(alternating) == count:
            ref = [grid[i] for i in alternating]
    return p, q, levelled, max(abs(e) for e in err)


def main():
    m, n = (int(sys.argv[1]), int(sys.argv[2])) if len(sys.argv) == 3 else (3, 4)
    p, q, levelled, largest = remez(m, n, D(math.tan(math.pi / 8)) ** 2)
    print(f"degree {m}/{n}: levelled error {float(levelled):.2e}, largest on the grid {float(largest):.2e}")
    print(f"const ATAN_P: [f64; {m + 1}] = [{', '.join(repr(float(c)) for c in p)}];")
    print(f"const ATAN_Q: [f64; {n}] = [{', '.join(repr(float(c)) for c in q[1:])}];")


if __name__ == "__main__":
    main()
