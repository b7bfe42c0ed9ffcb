#!/usr/bin/python3
"""Independent reference values for tests/oracles/test_gas_oracles.cpp.

Written separately from the C++ oracles (oracles/src/drag.cpp etc.), in the
interphase-coefficient form of the MFIX source (beta = DgA * eps_s, model A) rather
than the per-particle K form the C++ uses, and evaluated with mpmath at 40 digits, so a
transcription slip in either shows as a disagreement. Run with Debian's python:

    /usr/bin/python3 tests/oracles/gas_reference_values.py

and the printed numbers are the ones pasted into the test (17 significant digits).
"""
from mpmath import mp, mpf, sqrt, exp, log10, pi, findroot

mp.dps = 40

def Vp(d):
    return pi * d**3 / 6

# --- drag laws, beta form [kg/(m^3 s)] ------------------------------------------------
def cd_sn(Re):  # Schiller-Naumann with the Newton plateau above Re = 1000
    return 24 / Re * (1 + mpf('0.15') * Re**mpf('0.687')) if Re <= 1000 else mpf('0.44')

def beta_wen_yu(d, rg, mu, eg, w):
    es = 1 - eg
    Re = eg * rg * w * d / mu
    # MFIX DRAG_WEN_YU: DgA = 0.75 Cd w (eg rg) eg^-2.65 / d; F_gs = DgA * es
    return mpf('0.75') * cd_sn(Re) * w * eg * rg * eg**mpf('-2.65') / d * es

def beta_gidaspow(d, rg, mu, eg, w):
    es = 1 - eg
    if eg <= mpf('0.8'):  # MFIX: EPg <= 0.8 is Ergun
        return (150 * es * mu / (eg * d**2) + mpf('1.75') * rg * w / d) * es
    return beta_wen_yu(d, rg, mu, eg, w)

def beta_di_felice(d, rg, mu, eg, w):
    es = 1 - eg
    Re = eg * rg * w * d / mu
    cd = (mpf('0.63') + mpf('4.8') / sqrt(Re))**2
    chi = mpf('3.7') - mpf('0.65') * exp(-(mpf('1.5') - log10(Re))**2 / 2)
    K = mpf('0.125') * cd * rg * pi * d**2 * eg**(2 - chi) * w   # CFDEM / Zhou et al. 2010
    return K * es / Vp(d)

def F_bvk(phi, Re):
    eg = 1 - phi
    F0 = 10 * phi / eg**2 + eg**2 * (1 + mpf('1.5') * sqrt(phi))
    F1 = mpf('0.413') * Re / (24 * eg**2) * (1 / eg + 3 * eg * phi + mpf('8.4') * Re**mpf('-0.343')) \
         / (1 + mpf(10)**(3 * phi) * Re**(-(1 + 4 * phi) / 2))
    return F0 + F1

def beta_bvk(d, rg, mu, eg, w):
    es = 1 - eg
    Re = eg * rg * w * d / mu
    return 18 * mu * eg * es / d**2 * F_bvk(es, Re)   # MFIX DRAG_BVK * eps_s

def K_sn(d, rg, mu, w):
    Re = rg * w * d / mu
    return mpf(3) / 4 * cd_sn(Re) * rg * w / d * Vp(d)

def fmt(x):
    return mp.nstr(x, 17, min_fixed=-1, max_fixed=-1) if x != 0 else '0.0'

points = [  # d [m], rho_g, mu_g, eps_g, w [m/s]
    ('1e-4', '1.2', '1.8e-5', '0.95', '0.3'),
    ('5e-4', '1.2', '1.8e-5', '0.6', '1.0'),
    ('2e-3', '1.2', '1.8e-5', '0.85', '5.0'),
    ('5e-3', '1.2', '1.8e-5', '0.9', '10.0'),
    ('1e-3', '1000', '1e-3', '0.45', '0.01'),
    ('3e-4', '1.2', '1.8e-5', '0.7', '0.05'),
]
print('// d, rho_g, mu_g, eps_g, w, beta_wen_yu, beta_gidaspow, beta_di_felice, beta_bvk, K_sn')
for p in points:
    d, rg, mu, eg, w = map(mpf, p)
    vals = [beta_wen_yu(d, rg, mu, eg, w), beta_gidaspow(d, rg, mu, eg, w),
            beta_di_felice(d, rg, mu, eg, w), beta_bvk(d, rg, mu, eg, w), K_sn(d, rg, mu, w)]
    print('{' + ', '.join(list(p) + [fmt(v) for v in vals]) + '},')

# --- Gidaspow jump at eps_g = 0.8 (d = 5e-4, air, w = 1) ----------------------------
d, rg, mu, w = mpf('5e-4'), mpf('1.2'), mpf('1.8e-5'), mpf('1.0')
erg = (150 * mpf('0.2') * mu / (mpf('0.8') * d**2) + mpf('1.75') * rg * w / d) * mpf('0.2')
print('// Gidaspow at eps_g = 0.8: Ergun (MFIX, <= 0.8)', fmt(erg), 'Wen-Yu just above', fmt(beta_wen_yu(d, rg, mu, mpf('0.8'), w)))

# --- Wen-Yu Cd at Re = 1000 ----------------------------------------------------------
print('// SN Cd(1000) =', fmt(24 / mpf(1000) * (1 + mpf('0.15') * mpf(1000)**mpf('0.687'))))

# --- Case 6 terminal velocity (Garg et al. 2012 eq 48) -----------------------------
d, rp, rg, mu, u, g = mpf('1e-4'), mpf(2000), mpf('1.2'), mpf('1.8e-5'), mpf('0.4'), mpf('9.80665')
def f(w):
    Re = rg * w * d / mu
    return g * (rp - rg) / rp - mpf(3) / 4 * rg * cd_sn(Re) * w * w / (rp * d)
ws = findroot(f, mpf('0.4'))
print('// case 6 terminal slip', fmt(ws), 'particle velocity', fmt(u - ws))

# --- Minimum fluidisation (Ergun at eps = 0.4, d = 5e-4, rho_p = 2500, air) -------
d, rp, rg, mu, e, g = mpf('5e-4'), mpf(2500), mpf('1.2'), mpf('1.8e-5'), mpf('0.4'), mpf('9.80665')
es = 1 - e
def ergun(U):
    return 150 * mu * es**2 * U / (e**3 * d**2) + mpf('1.75') * rg * es * U**2 / (e**3 * d)
Umf = findroot(lambda U: ergun(U) - es * (rp - rg) * g, mpf('0.1'))
Ar = d**3 * rg * (rp - rg) * g / mu**2
Re_wy = sqrt(mpf('33.7')**2 + mpf('0.0408') * Ar) - mpf('33.7')
print('// U_mf Ergun eps=0.4', fmt(Umf), ' Wen-Yu 1966 estimate', fmt(Re_wy * mu / (rg * d)), ' Ar', fmt(Ar))
# same bed, BVK and Di Felice (pressure gradient beta(eps, U/eps) U / eps^2)
for name, law in (('bvk', beta_bvk), ('di_felice', beta_di_felice), ('wen_yu', beta_wen_yu)):
    U = findroot(lambda U: law(d, rg, mu, e, U / e) * U / e**2 - es * (rp - rg) * g, mpf('0.1'))
    print('// U_mf', name, fmt(U))

# --- Suspension steady slip (Wen-Yu, eps_g = 0.9, d = 1e-4, rho_p = 2500, air) -------
d, rp, rg, mu, e, g = mpf('1e-4'), mpf(2500), mpf('1.2'), mpf('1.8e-5'), mpf('0.9'), mpf('9.80665')
es = 1 - e
w = findroot(lambda w: beta_wen_yu(d, rg, mu, e, w) * w - es * e * (rp - rg) * g, mpf('0.1'))
print('// suspension steady slip wen_yu eps=0.9', fmt(w))
