//! The named strength families and every composed term against independent transcriptions
//! of their published formulas.
//!
//! GOAL: the flow stress the kernel computes for Johnson-Cook, Zerilli-Armstrong (BCC and FCC),
//! modified Johnson-Cook, two-part-rate Johnson-Cook and every hardening x rate x thermal
//! composition the diagnosis builds is the published law, and its strain and rate
//! derivatives (the return mapping's Newton slopes) are the law's. The kernel's own
//! checks (`stoss verify`) compare the return mapping with the kernel's `flow_stress`, which
//! proves consistency, not the law: this file is the law's reference.
//! SETUP: each formula written out here from its source with the `libm` crate's `pow`, `log`,
//! `exp` and `sqrt` (FreeBSD msun; not the kernel's table-driven functions, not its terms),
//! evaluated on a grid of plastic strains (0 to 2), plastic rates (0, below and above the
//! reference rate, to 1e5 /s) and temperatures (below the reference, up to the melt); the
//! derivatives against central differences of the transcription.
//! REFERENCE: Johnson & Cook (1983), Proc. 7th Int. Symp. Ballistics, eq. 1 (rate factor 1
//! below the reference rate, as LS-DYNA's *MAT_015); Zerilli & Armstrong (1987), J. Appl.
//! Phys. 61, eqs. 5-6 (BCC: `sa + C1 exp(-C3 T + C4 T ln e*) + C5 eps^n`; FCC: `sa + C2 eps^(1/2)
//! exp(-C3 T + C4 T ln e*)`); seed 000 (Ryan et al. 2022) sec. 2 for MJC (`A + B eps^n + Q1 (1 -
//! exp(-c1 eps)) + Q2 (1 - exp(-c2 eps))`, rate `(1 + e*)^beta`) and TJC (the same hardening,
//! rate `(1 + deps/e01)^beta1 (1 + deps/e02)^beta2`), both with `1 - T*^m`; Preston, Tonks &
//! Wallace (2003), J. Appl. Phys. 93, eqs. 7, 11, 12 and 15 (`sigma = 2 G tau^`); Khan, Suh &
//! Kazmi (2004), Int. J. Plasticity 20, eq. 1 (`[A + B (1 - ln e'/ln D0p)^n1 eps^n0] (e'/e0)^C
//! (1 - T*^m)`); Voce's law integrated at a constant saturation `sigma_s - (sigma_s - sigma_0)
//! exp(-theta_0 eps / sigma_s)` with Kocks' (1976) `sigma_s = sigma_s0 (e'/e_s0)^(T/T_A)`;
//! Follansbee & Kocks (1988), Acta Metall. 36, eqs. 2, 3, 6-8 and 10 for the Mechanical
//! Threshold Stress, its structure evolution integrated here by Runge-Kutta steps (the kernel
//! solves its closed-form integral instead).

use stoss_kernel::strength::{
    ComposedStrength, CrystalStructure, Hardening, JohnsonCook, KhanHuangLiang,
    MechanicalThresholdStress, ModifiedJohnsonCook, PrestonTonksWallace, RateTerm, Strength,
    ThermalTerm, TwoRateJohnsonCook, VoceKocks, ZerilliArmstrong,
};

/// Relative agreement of the value: measured at most 4.4e-16 (two ulps of composition
/// differences; JC agrees to the bit); a wrong term or branch differs by far more.
const VALUE_TOLERANCE: f64 = 2e-15;
/// Relative agreement of a derivative with a central difference of the transcription
/// (measured at most 6.5e-7: the difference's own truncation and round-off).
const SLOPE_TOLERANCE: f64 = 2e-6;
/// The same for Preston-Tonks-Wallace and Voce-Kocks (see their tests). PTW: near the melting
/// point at slow rates its rate slope is about 1e-8 of the flow stress per 1/s, and the
/// transcription's central difference (step 1e-4 of the rate) then carries round-off of
/// `ulp(sigma) / h`, about 1e-6 of the comparison's scale (measured 2.5e-6 for tantalum at
/// 1200 K, 0.5 /s; copper 6.9e-7); a wrong branch or sign differs by order 1.
const COUPLED_SLOPE_TOLERANCE: f64 = 1e-5;

/// `T* = (T - Tr) / (Tm - Tr)` in [0, 1]; `1 - T*^m`, exactly 1 at or below `Tr`.
fn johnson_cook_thermal(t: f64, tr: f64, tm: f64, m: f64) -> f64 {
    let star = ((t - tr) / (tm - tr)).clamp(0.0, 1.0);
    if star == 0.0 {
        1.0
    } else {
        1.0 - libm::pow(star, m)
    }
}

fn jc_reference(c: &JohnsonCook, eps: f64, rate: f64, t: f64) -> f64 {
    let star = rate / c.reference_rate;
    let rate_factor = if star > 1.0 {
        1.0 + c.rate_sensitivity * libm::log(star)
    } else {
        1.0
    };
    (c.yield_stress + c.hardening_modulus * libm::pow(eps, c.hardening_exponent))
        * rate_factor
        * johnson_cook_thermal(
            t,
            c.reference_temperature,
            c.melting_temperature,
            c.thermal_exponent,
        )
}

fn za_reference(c: &ZerilliArmstrong, eps: f64, rate: f64, t: f64) -> f64 {
    let star = (rate / c.reference_rate).max(ZerilliArmstrong::MINIMUM_RATE_RATIO);
    let activation = libm::exp(-c.c3 * t + c.c4 * t * libm::log(star));
    match c.structure {
        CrystalStructure::Bcc => {
            c.athermal_stress + c.c1 * activation + c.c5 * libm::pow(eps, c.exponent)
        }
        CrystalStructure::Fcc => c.athermal_stress + c.c2 * libm::sqrt(eps) * activation,
    }
}

/// Seed 000's MJC / TJC hardening: power plus two Voce terms.
fn voce_hardening(a: f64, b: f64, n: f64, q: [(f64, f64); 2], eps: f64) -> f64 {
    a + b * libm::pow(eps, n)
        + q.iter()
            .map(|(q, c)| q * (1.0 - libm::exp(-c * eps)))
            .sum::<f64>()
}

fn mjc_reference(c: &ModifiedJohnsonCook, eps: f64, rate: f64, t: f64) -> f64 {
    voce_hardening(
        c.yield_stress,
        c.hardening_modulus,
        c.hardening_exponent,
        [
            (c.saturation_stress_1, c.saturation_rate_1),
            (c.saturation_stress_2, c.saturation_rate_2),
        ],
        eps,
    ) * libm::pow(1.0 + rate / c.reference_rate, c.rate_exponent)
        * johnson_cook_thermal(
            t,
            c.reference_temperature,
            c.melting_temperature,
            c.thermal_exponent,
        )
}

fn tjc_reference(c: &TwoRateJohnsonCook, eps: f64, rate: f64, t: f64) -> f64 {
    voce_hardening(
        c.yield_stress,
        c.hardening_modulus,
        c.hardening_exponent,
        [
            (c.saturation_stress_1, c.saturation_rate_1),
            (c.saturation_stress_2, c.saturation_rate_2),
        ],
        eps,
    ) * libm::pow(1.0 + rate / c.reference_rate_1, c.rate_exponent_1)
        * libm::pow(1.0 + rate / c.reference_rate_2, c.rate_exponent_2)
        * johnson_cook_thermal(
            t,
            c.reference_temperature,
            c.melting_temperature,
            c.thermal_exponent,
        )
}

/// The grid: strains, rates and temperatures (K) covering every branch of the laws.
/// Preston-Tonks-Wallace (2003), written from the paper: `T^ = T/Tm` in [0, 1], `G = G0 (1 -
/// alpha T^)`, `xi' = (1/2) (4 pi rho / 3 m)^(1/3) (G/rho)^(1/2)`, `u = max(rate, 1e-8) / (gamma
/// xi')`, eqs. 11-12 for the saturation and yield stresses, eq. 7 (its `p -> 0` limit for `p =
/// 0`) for the hardening, `sigma = 2 G tau^`.
fn ptw_reference(c: &PrestonTonksWallace, eps: f64, rate: f64, t: f64) -> f64 {
    let th = (t / c.melting_temperature).clamp(0.0, 1.0);
    let g = c.shear_modulus_0 * (1.0 - c.alpha * th);
    let atom = c.atomic_mass * 1.660_539_066_60e-27;
    let xi = 0.5
        * libm::cbrt(4.0 * std::f64::consts::PI * c.density / (3.0 * atom))
        * libm::sqrt(g / c.density);
    let u = rate.max(1e-8) / (c.gamma * xi);
    let z = libm::erf(c.kappa * th * libm::log(1.0 / u));
    let shock_s = c.s0 * libm::pow(u, c.beta);
    let s = (c.s0 - (c.s0 - c.s_inf) * z).max(shock_s);
    let y = (c.y0 - (c.y0 - c.y_inf) * z).max((c.y1 * libm::pow(u, c.y2)).min(shock_s));
    let psi = eps.max(0.0);
    // Eq. 7 and its p -> 0 limit, each rearranged (algebraically equal) as y^ plus the
    // hardening gained, so that no digits cancel where t^ is near y^ (small strain).
    let tau = if s <= y {
        s
    } else if c.p == 0.0 {
        y + (s - y) * (1.0 - libm::exp(-c.theta * psi / (s - y)))
    } else {
        // s^ + A ln(1 - (1 - e^-x) e^-k) = y^ + A ln(1 + (e^x - 1)(1 - e^-k)), A = (s0 - y^)/p,
        // x = (s^ - y^)/A, k = theta psi / (A (e^x - 1)).
        let a = (c.s0 - y) / c.p;
        let grown = libm::expm1((s - y) / a);
        y + a * libm::log1p(grown * -libm::expm1(-c.theta * psi / (a * grown)))
    };
    2.0 * g * tau
}

/// Khan-Huang-Liang (Khan, Suh & Kazmi 2004 eq. 1), the rate held at 1e-6 /s below it and the
/// coupled factor 0 at and above `D0p`.
fn khl_reference(c: &KhanHuangLiang, eps: f64, rate: f64, t: f64) -> f64 {
    let rate = rate.max(1e-6);
    let w = 1.0 - libm::log(rate) / libm::log(c.upper_rate);
    let coupled = if w > 0.0 {
        libm::pow(w, c.coupling_exponent)
    } else {
        0.0
    };
    let hardening = if eps > 0.0 {
        c.hardening_modulus * libm::pow(eps, c.hardening_exponent)
    } else {
        0.0
    };
    (c.yield_stress + hardening * coupled)
        * libm::pow(rate / c.reference_rate, c.rate_sensitivity)
        * johnson_cook_thermal(
            t,
            c.reference_temperature,
            c.melting_temperature,
            c.thermal_exponent,
        )
}

/// Voce-Kocks: Voce's law to Kocks' saturation, the rate held at 1e-6 /s below it and the
/// saturation at or above 1e-6 of the yield stress.
fn vk_reference(c: &VoceKocks, eps: f64, rate: f64, t: f64) -> f64 {
    let saturation = (c.saturation_stress
        * libm::pow(
            rate.max(1e-6) / c.saturation_reference_rate,
            t / c.activation_temperature,
        ))
    .max(1e-6 * c.yield_stress);
    // sigma_s - (sigma_s - sigma_0) e^-k, written as sigma_0 + (sigma_s - sigma_0)(1 - e^-k)
    // (algebraically equal): the printed form cancels where the saturation is far below the
    // yield stress (hot and slow).
    c.yield_stress
        - (saturation - c.yield_stress)
            * libm::expm1(-c.initial_hardening * eps.max(0.0) / saturation)
}

/// Mechanical Threshold Stress: Follansbee & Kocks' law with `d sigma_e / d eps = theta_0 (1
/// - tanh(alpha sigma_e / sigma_es) / tanh(alpha))` integrated from 0 by 4000 classical
/// Runge-Kutta steps (a fixed count, so that the truncation error is smooth in the strain and
/// the slopes' central differences see the law), with the kernel's stated floors: rate 1e-6
/// /s, `mu/mu_0` 1e-6, `theta_0` 0, `sigma_es` between 1e-6 and 1e6 `sigma_es0`.
fn mts_reference(c: &MechanicalThresholdStress, eps: f64, rate: f64, t: f64) -> f64 {
    let rate = rate.max(1e-6);
    let mu = if t > 0.0 {
        c.shear_modulus_0 - c.shear_modulus_drop / (libm::exp(c.varshni_temperature / t) - 1.0)
    } else {
        c.shear_modulus_0
    };
    let mu = mu.max(1e-6 * c.shear_modulus_0);
    let s = |g0: f64, e0: f64, p: f64, q: f64| {
        let x = c.boltzmann_per_burgers_cubed * t / (g0 * mu) * libm::log(e0 / rate);
        if x <= 0.0 {
            1.0
        } else if x >= 1.0 {
            0.0
        } else {
            libm::pow(1.0 - libm::pow(x, 1.0 / q), 1.0 / p)
        }
    };
    let s_i = if c.intrinsic_stress > 0.0 {
        s(
            c.intrinsic_activation_energy,
            c.intrinsic_reference_rate,
            c.intrinsic_p,
            c.intrinsic_q,
        )
    } else {
        0.0
    };
    let s_e = s(
        c.structure_activation_energy,
        c.structure_reference_rate,
        c.structure_p,
        c.structure_q,
    );
    let sigma_es = (c.saturation_stress
        * libm::pow(
            rate / c.saturation_reference_rate,
            c.boltzmann_per_burgers_cubed * t / (c.saturation_activation_energy * mu),
        ))
    .clamp(1e-6 * c.saturation_stress, 1e6 * c.saturation_stress);
    let theta_0 =
        (c.hardening_a0 + c.hardening_a1 * libm::log(rate) + c.hardening_a2 * libm::sqrt(rate)
            - c.hardening_a3 * t)
            .max(0.0);
    let alpha = c.hardening_shape;
    let law = |sigma_e: f64| {
        let x = sigma_e / sigma_es;
        let f = if alpha == 0.0 {
            x
        } else {
            libm::tanh(alpha * x) / libm::tanh(alpha)
        };
        theta_0 * (1.0 - f)
    };
    let steps = 4000;
    let h = eps.max(0.0) / steps as f64;
    let mut sigma_e = 0.0;
    for _ in 0..steps {
        let k1 = law(sigma_e);
        let k2 = law(sigma_e + 0.5 * h * k1);
        let k3 = law(sigma_e + 0.5 * h * k2);
        let k4 = law(sigma_e + h * k3);
        sigma_e += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    c.athermal_stress + (s_i * c.intrinsic_stress + s_e * sigma_e) * mu / c.shear_modulus_0
}

const STRAINS: [f64; 7] = [0.0, 1e-4, 0.01, 0.05, 0.2, 0.8, 2.0];
const RATES: [f64; 8] = [0.0, 1e-3, 0.5, 1.0, 2.0, 100.0, 3000.0, 1e5];
const TEMPERATURES: [f64; 6] = [250.0, 298.0, 400.0, 700.0, 1200.0, 1700.0];

/// Compare `strength` with `reference` on the grid: values, and the strain and rate slopes
/// where the law is smooth (away from `eps = 0`, the rate floor and JC's kink at the reference
/// rate, where a central difference straddles a branch). Returns the largest relative errors.
fn compare(
    name: &str,
    strength: Strength,
    reference: &dyn Fn(f64, f64, f64) -> f64,
    kink_rate: f64,
) -> (f64, f64) {
    compare_within(name, strength, reference, kink_rate, SLOPE_TOLERANCE)
}

/// [`compare`] with the slopes' tolerance given.
fn compare_within(
    name: &str,
    strength: Strength,
    reference: &dyn Fn(f64, f64, f64) -> f64,
    kink_rate: f64,
    slope_tolerance: f64,
) -> (f64, f64) {
    compare_with_tolerances(
        name,
        strength,
        reference,
        kink_rate,
        VALUE_TOLERANCE,
        slope_tolerance,
    )
}

/// [`compare`] with the value's and the slopes' tolerances given.
fn compare_with_tolerances(
    name: &str,
    strength: Strength,
    reference: &dyn Fn(f64, f64, f64) -> f64,
    kink_rate: f64,
    value_tolerance: f64,
    slope_tolerance: f64,
) -> (f64, f64) {
    let (mut worst_value, mut worst_slope) = (0.0_f64, 0.0_f64);
    for &t in &TEMPERATURES {
        for &rate in &RATES {
            for &eps in &STRAINS {
                let kernel = strength.flow_stress(eps, rate, t);
                let exact = reference(eps, rate, t);
                let error = (kernel.value - exact).abs() / exact.abs().max(1.0);
                assert!(
                    error <= value_tolerance,
                    "{name}: sigma_y({eps}, {rate}, {t}) = {} against {exact} ({error:e})",
                    kernel.value
                );
                worst_value = worst_value.max(error);
                if exact <= 0.0 {
                    continue;
                }
                if eps >= 1e-3 {
                    let h = 1e-4 * eps;
                    let slope =
                        (reference(eps + h, rate, t) - reference(eps - h, rate, t)) / (2.0 * h);
                    let error =
                        (kernel.d_plastic_strain - slope).abs() / slope.abs().max(exact * 1e-3);
                    assert!(
                        error <= slope_tolerance,
                        "{name}: d/deps at ({eps}, {rate}, {t}) = {} against {slope} ({error:e})",
                        kernel.d_plastic_strain
                    );
                    worst_slope = worst_slope.max(error);
                }
                let smooth_rate = rate > 0.0 && (rate / kink_rate - 1.0).abs() > 1e-3;
                if smooth_rate {
                    let h = 1e-4 * rate;
                    let slope =
                        (reference(eps, rate + h, t) - reference(eps, rate - h, t)) / (2.0 * h);
                    // Relative to the stress change over a decade of rate, so that a slope
                    // of zero (below JC's reference rate) is compared at a meaningful scale.
                    let scale = slope.abs().max(exact * 1e-6 / rate);
                    let error = (kernel.d_rate - slope).abs() / scale;
                    assert!(
                        error <= slope_tolerance,
                        "{name}: d/drate at ({eps}, {rate}, {t}) = {} against {slope} ({error:e})",
                        kernel.d_rate
                    );
                    worst_slope = worst_slope.max(error);
                }
            }
        }
    }
    eprintln!("{name}: value {worst_value:.1e}, slopes {worst_slope:.1e}");
    (worst_value, worst_slope)
}

#[test]
fn johnson_cook_is_the_published_law() {
    let c = JohnsonCook::STEEL_4340;
    compare(
        "JC 4340",
        c.into(),
        &|e, r, t| jc_reference(&c, e, r, t),
        c.reference_rate,
    );
}

#[test]
fn zerilli_armstrong_bcc_and_fcc_are_the_published_laws() {
    let bcc = ZerilliArmstrong::ARMCO_IRON;
    compare(
        "ZA BCC Armco iron",
        bcc.into(),
        &|e, r, t| za_reference(&bcc, e, r, t),
        bcc.reference_rate * ZerilliArmstrong::MINIMUM_RATE_RATIO,
    );
    // Zerilli & Armstrong (1987) OFHC copper: C2 890 MPa, C3 0.0028 /K, C4 0.000115 /K,
    // athermal stress 46.5 MPa.
    let fcc = ZerilliArmstrong {
        structure: CrystalStructure::Fcc,
        athermal_stress: 46.5e6,
        c1: 0.0,
        c2: 890.0e6,
        c3: 0.0028,
        c4: 0.000115,
        c5: 0.0,
        exponent: 0.0,
        reference_rate: 1.0,
    };
    compare(
        "ZA FCC OFHC copper",
        fcc.into(),
        &|e, r, t| za_reference(&fcc, e, r, t),
        fcc.reference_rate * ZerilliArmstrong::MINIMUM_RATE_RATIO,
    );
}

#[test]
fn preston_tonks_wallace_is_the_published_law() {
    // Tantalum (p = 0) and copper (p = 2) of PTW (2003) table II; copper's yield stress is in
    // the overdriven branch at 1e5 /s, so both regimes are compared.
    let ta = PrestonTonksWallace::TANTALUM;
    compare_within(
        "PTW tantalum",
        ta.into(),
        &|e, r, t| ptw_reference(&ta, e, r, t),
        PrestonTonksWallace::MINIMUM_RATE,
        COUPLED_SLOPE_TOLERANCE,
    );
    let cu = PrestonTonksWallace::COPPER;
    compare_within(
        "PTW copper",
        cu.into(),
        &|e, r, t| ptw_reference(&cu, e, r, t),
        PrestonTonksWallace::MINIMUM_RATE,
        COUPLED_SLOPE_TOLERANCE,
    );
    // At small strain, where eq. 7 as printed cancels most of its digits (copper, strain 1e-4,
    // 1e-3 /s, 250 K), the value and rate slope against a 50-digit evaluation of the printed
    // form (mpmath, mp.dps = 50): 10227903.182363766 Pa and 2282.2018714690283 Pa s.
    let at = Strength::from(cu).flow_stress(1e-4, 1e-3, 250.0);
    assert!(
        (at.value / 10_227_903.182_363_766 - 1.0).abs() < 1e-14,
        "{}",
        at.value
    );
    assert!(
        (at.d_rate / 2_282.201_871_469_028_3 - 1.0).abs() < 1e-8,
        "{}",
        at.d_rate
    );
}

#[test]
fn khan_huang_liang_is_the_published_law() {
    // Constants in the range of Khan et al.'s titanium fits (their D0p 1e6 /s).
    let khl = KhanHuangLiang {
        yield_stress: 1000.0e6,
        hardening_modulus: 800.0e6,
        hardening_exponent: 0.4,
        coupling_exponent: 0.8,
        rate_sensitivity: 0.012,
        reference_rate: 1.0,
        upper_rate: 1.0e6,
        thermal_exponent: 0.8,
        reference_temperature: 298.0,
        melting_temperature: 1878.0,
    };
    compare(
        "KHL",
        khl.into(),
        &|e, r, t| khl_reference(&khl, e, r, t),
        KhanHuangLiang::MINIMUM_RATE,
    );
}

#[test]
fn mechanical_threshold_stress_is_follansbee_and_kocks_law() {
    // The reference integrates the structure's evolution numerically: its 4000 Runge-Kutta
    // steps leave a truncation error of a few 1e-14 of the flow stress (measured 3.1e-14), so
    // values agree to 1e-12 rather than to round-off; the slopes as for the other coupled
    // families. Copper (Follansbee & Kocks' set, alpha 2, no intrinsic barrier) and a BCC-like
    // variant (HY-100's intrinsic barrier shape with sigma_i 300 MPa, a_3 1 MPa/K, and the
    // Voce limit alpha = 0).
    let (g, e, p, q) = MechanicalThresholdStress::BCC_INTRINSIC_SHAPE;
    for (name, mts) in [
        ("MTS copper", MechanicalThresholdStress::COPPER),
        (
            "MTS BCC-like",
            MechanicalThresholdStress {
                intrinsic_stress: 300.0e6,
                intrinsic_activation_energy: g,
                intrinsic_reference_rate: e,
                intrinsic_p: p,
                intrinsic_q: q,
                hardening_a3: 1.0e6,
                hardening_shape: 0.0,
                ..MechanicalThresholdStress::COPPER
            },
        ),
    ] {
        compare_with_tolerances(
            name,
            mts.into(),
            &|e, r, t| mts_reference(&mts, e, r, t),
            MechanicalThresholdStress::MINIMUM_RATE,
            1e-12,
            COUPLED_SLOPE_TOLERANCE,
        );
    }
}

#[test]
fn voce_kocks_is_voces_law_to_kocks_saturation() {
    // Hot and slow (1700 K, 1e-3 /s) the saturation stress lies 40 times below the yield
    // stress, and the saturated flow stress is the difference of two nearly equal stresses:
    // the transcription's central difference then carries round-off of a few 1e-6 of the
    // comparison's scale (measured 2.4e-6).
    let vk = VoceKocks::ILLUSTRATIVE;
    compare_within(
        "Voce-Kocks",
        vk.into(),
        &|e, r, t| vk_reference(&vk, e, r, t),
        VoceKocks::MINIMUM_RATE,
        COUPLED_SLOPE_TOLERANCE,
    );
}

#[test]
fn modified_and_two_part_rate_johnson_cook_are_seed_000s_laws() {
    // Constants inside seed 000's bounds (its sec. 4: Q 0-3 GPa, c 0-2000, beta 0-0.1), with
    // both Voce terms and both rate parts active.
    let mjc = ModifiedJohnsonCook {
        yield_stress: 1.2e9,
        hardening_modulus: 0.4e9,
        hardening_exponent: 0.3,
        saturation_stress_1: 0.25e9,
        saturation_rate_1: 40.0,
        saturation_stress_2: 0.6e9,
        saturation_rate_2: 3.0,
        rate_exponent: 0.012,
        reference_rate: 1.0,
        thermal_exponent: 1.1,
        reference_temperature: 298.0,
        melting_temperature: 1793.0,
    };
    compare(
        "MJC",
        mjc.into(),
        &|e, r, t| mjc_reference(&mjc, e, r, t),
        f64::INFINITY,
    );
    let tjc = TwoRateJohnsonCook {
        yield_stress: 1.2e9,
        hardening_modulus: 0.4e9,
        hardening_exponent: 0.3,
        saturation_stress_1: 0.25e9,
        saturation_rate_1: 40.0,
        saturation_stress_2: 0.6e9,
        saturation_rate_2: 3.0,
        rate_exponent_1: 0.008,
        reference_rate_1: 1e-3,
        rate_exponent_2: 0.05,
        reference_rate_2: 1e3,
        thermal_exponent: 1.1,
        reference_temperature: 298.0,
        melting_temperature: 1793.0,
    };
    compare(
        "TJC",
        tjc.into(),
        &|e, r, t| tjc_reference(&tjc, e, r, t),
        f64::INFINITY,
    );
}

#[test]
fn a_wrong_term_is_caught_by_the_references() {
    // GOAL: the comparison can fail: Johnson-Cook with the rate term applied below the
    // reference rate (a common transcription slip: `1 + C ln e*` for e* < 1) differs from
    // the kernel's law far beyond the tolerance.
    let c = JohnsonCook::STEEL_4340;
    let strength: Strength = c.into();
    let slipped = |e: f64, r: f64, t: f64| {
        let star: f64 = r / c.reference_rate;
        jc_reference(&c, e, r, t) * (1.0 + c.rate_sensitivity * libm::log(star))
    };
    let kernel = strength.flow_stress(0.1, 1e-3, 298.0).value;
    let wrong = slipped(0.1, 1e-3, 298.0);
    assert!((kernel - wrong).abs() / kernel > 1e3 * VALUE_TOLERANCE);
}

/// `T*` clamped to [0, 1].
fn homologous(t: f64, tr: f64, tm: f64) -> f64 {
    ((t - tr) / (tm - tr)).clamp(0.0, 1.0)
}

fn hardening_reference(h: &Hardening, eps: f64) -> f64 {
    let voce = |q: f64, c: f64| q * (1.0 - libm::exp(-c * eps));
    match *h {
        Hardening::Power {
            yield_stress,
            hardening_modulus,
            exponent,
        } => yield_stress + hardening_modulus * libm::pow(eps, exponent),
        Hardening::Voce2 {
            yield_stress,
            saturation_stress_1,
            saturation_rate_1,
            saturation_stress_2,
            saturation_rate_2,
        } => {
            yield_stress
                + voce(saturation_stress_1, saturation_rate_1)
                + voce(saturation_stress_2, saturation_rate_2)
        }
        Hardening::PowerVoce2 {
            yield_stress,
            hardening_modulus,
            exponent,
            saturation_stress_1,
            saturation_rate_1,
            saturation_stress_2,
            saturation_rate_2,
        } => {
            yield_stress
                + hardening_modulus * libm::pow(eps, exponent)
                + voce(saturation_stress_1, saturation_rate_1)
                + voce(saturation_stress_2, saturation_rate_2)
        }
    }
}

fn rate_reference(r: &RateTerm, rate: f64, t: f64) -> f64 {
    let log_factor = |c: f64, e0: f64| {
        let star = rate / e0;
        if star > 1.0 {
            1.0 + c * libm::log(star)
        } else {
            1.0
        }
    };
    let power = |beta: f64, e0: f64| libm::pow(1.0 + rate / e0, beta);
    match *r {
        RateTerm::None => 1.0,
        RateTerm::JohnsonCookLog {
            rate_sensitivity,
            reference_rate,
        } => log_factor(rate_sensitivity, reference_rate),
        RateTerm::Power {
            exponent,
            reference_rate,
        } => power(exponent, reference_rate),
        RateTerm::TwoPart {
            exponent_1,
            reference_rate_1,
            exponent_2,
            reference_rate_2,
        } => power(exponent_1, reference_rate_1) * power(exponent_2, reference_rate_2),
        RateTerm::LogUpturn {
            rate_sensitivity,
            reference_rate,
            upturn_exponent,
            upturn_rate,
        } => log_factor(rate_sensitivity, reference_rate) * power(upturn_exponent, upturn_rate),
        RateTerm::LogThermal {
            rate_sensitivity,
            reference_rate,
            coupling,
            reference_temperature,
            melting_temperature,
        } => {
            let star = homologous(t, reference_temperature, melting_temperature);
            log_factor(rate_sensitivity * (1.0 + coupling * star), reference_rate)
        }
        RateTerm::CowperSymonds {
            rate_constant,
            exponent,
        } => 1.0 + libm::pow(rate / rate_constant, 1.0 / exponent),
    }
}

fn thermal_reference(th: &ThermalTerm, t: f64) -> f64 {
    let power = |m: f64, tr: f64, tm: f64| {
        let star = homologous(t, tr, tm);
        if star == 0.0 {
            1.0
        } else {
            1.0 - libm::pow(star, m)
        }
    };
    match *th {
        ThermalTerm::None => 1.0,
        ThermalTerm::HomologousPower {
            exponent,
            reference_temperature,
            melting_temperature,
        } => power(exponent, reference_temperature, melting_temperature),
        ThermalTerm::HomologousPowerDrop {
            exponent,
            reference_temperature,
            melting_temperature,
            drop,
            drop_start_temperature,
            drop_end_temperature,
        } => {
            let x = ((t - drop_start_temperature)
                / (drop_end_temperature - drop_start_temperature))
                .clamp(0.0, 1.0);
            power(exponent, reference_temperature, melting_temperature)
                * (1.0 - drop * x * x * (3.0 - 2.0 * x))
        }
        ThermalTerm::Linear {
            reference_temperature,
            melting_temperature,
        } => 1.0 - homologous(t, reference_temperature, melting_temperature),
    }
}

#[test]
fn every_composed_term_is_its_published_form() {
    // GOAL: the terms the diagnosis composes (and a material file may name) are their
    //       published forms too, in every combination: hardening x rate x thermal.
    // SETUP: Ludwik power, two-term Voce and power + Voce hardening; no rate, JC log, power,
    //        two-part, JC log with a high-rate upturn, JC log with temperature-dependent
    //        sensitivity and Cowper-Symonds rates; no softening, JC `1 - T*^m`, JC with a
    //        smooth-step drop (600-900 K, 30 %) and linear softening; the grid of `compare`.
    // REFERENCE: Ludwik (1909) `A + B eps^n`; Voce (1948) `Q (1 - exp(-c eps))`; Johnson &
    //        Cook (1983); seed 000 sec. 2 (power and two-part rates); Cowper & Symonds
    //        (1957) `1 + (deps/D)^(1/q)`; the upturn, coupling and drop terms as the kernel's
    //        documentation writes them (`rate.rs`, `thermal.rs`: `(1 + C ln e*)(1 +
    //        deps/e_up)^beta`, `1 + C (1 + kappa T*) ln e*`, `(1 - T*^m)(1 - d x^2 (3 - 2x))`),
    //        each transcribed here with libm.
    let hardenings = [
        Hardening::Power {
            yield_stress: 792e6,
            hardening_modulus: 510e6,
            exponent: 0.26,
        },
        Hardening::Voce2 {
            yield_stress: 900e6,
            saturation_stress_1: 250e6,
            saturation_rate_1: 40.0,
            saturation_stress_2: 600e6,
            saturation_rate_2: 3.0,
        },
        Hardening::PowerVoce2 {
            yield_stress: 1.2e9,
            hardening_modulus: 0.4e9,
            exponent: 0.3,
            saturation_stress_1: 0.25e9,
            saturation_rate_1: 40.0,
            saturation_stress_2: 0.6e9,
            saturation_rate_2: 3.0,
        },
    ];
    let rates = [
        (RateTerm::None, f64::INFINITY),
        (
            RateTerm::JohnsonCookLog {
                rate_sensitivity: 0.014,
                reference_rate: 1.0,
            },
            1.0,
        ),
        (
            RateTerm::Power {
                exponent: 0.012,
                reference_rate: 1.0,
            },
            f64::INFINITY,
        ),
        (
            RateTerm::TwoPart {
                exponent_1: 0.008,
                reference_rate_1: 1e-3,
                exponent_2: 0.05,
                reference_rate_2: 1e3,
            },
            f64::INFINITY,
        ),
        (
            RateTerm::LogUpturn {
                rate_sensitivity: 0.014,
                reference_rate: 1.0,
                upturn_exponent: 0.08,
                upturn_rate: 1e3,
            },
            1.0,
        ),
        (
            RateTerm::LogThermal {
                rate_sensitivity: 0.014,
                reference_rate: 1.0,
                coupling: 2.5,
                reference_temperature: 298.0,
                melting_temperature: 1793.0,
            },
            1.0,
        ),
        (
            RateTerm::CowperSymonds {
                rate_constant: 40.0,
                exponent: 5.0,
            },
            f64::INFINITY,
        ),
    ];
    let thermals = [
        ThermalTerm::None,
        ThermalTerm::HomologousPower {
            exponent: 1.03,
            reference_temperature: 298.0,
            melting_temperature: 1793.0,
        },
        ThermalTerm::HomologousPowerDrop {
            exponent: 1.03,
            reference_temperature: 298.0,
            melting_temperature: 1793.0,
            drop: 0.3,
            drop_start_temperature: 600.0,
            drop_end_temperature: 900.0,
        },
        ThermalTerm::Linear {
            reference_temperature: 298.0,
            melting_temperature: 1793.0,
        },
    ];
    let mut compared = 0;
    for hardening in hardenings {
        for (rate, kink) in rates {
            for thermal in thermals {
                let strength = Strength::Composed(ComposedStrength {
                    hardening,
                    rate,
                    thermal,
                });
                compare(
                    &format!("{hardening:?} x {rate:?} x {thermal:?}"),
                    strength,
                    &|e, r, t| {
                        hardening_reference(&hardening, e)
                            * rate_reference(&rate, r, t)
                            * thermal_reference(&thermal, t)
                    },
                    kink,
                );
                compared += 1;
            }
        }
    }
    assert_eq!(compared, 84);
}
