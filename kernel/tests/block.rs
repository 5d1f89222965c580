//! The group and block updates (`update_lanes`, `update_block`) against the one-point update,
//! bit for bit.

use stoss_kernel::damage::{Failure, JohnsonCookFailure};
use stoss_kernel::eos::{Eos, MieGruneisen};
use stoss_kernel::strength::{
    KhanHuangLiang, MechanicalThresholdStress, ModifiedJohnsonCook, PrestonTonksWallace, Strength,
    TwoRateJohnsonCook, VoceKocks, ZerilliArmstrong,
};
use stoss_kernel::{
    update, update_block, update_lanes, Material, MaterialState, RateTreatment, StepInput,
    StepOutput, UpdateError,
};

/// A reproducible stream of numbers in [0, 1).
struct Stream(u64);

impl Stream {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The strength models the kernel has, each on 4340's elasticity, EoS and heating.
fn materials() -> Vec<(&'static str, Material)> {
    let base = Material::STEEL_4340;
    let mut list: Vec<(&'static str, Material)> = vec![
        ("jc", base),
        ("za-bcc", base.with_strength(ZerilliArmstrong::ARMCO_IRON)),
        (
            "mjc",
            base.with_strength(ModifiedJohnsonCook {
                yield_stress: 792.0e6,
                hardening_modulus: 510.0e6,
                hardening_exponent: 0.26,
                saturation_stress_1: 100.0e6,
                saturation_rate_1: 10.0,
                saturation_stress_2: 50.0e6,
                saturation_rate_2: 100.0,
                rate_exponent: 0.01,
                reference_rate: 1.0,
                thermal_exponent: 1.03,
                reference_temperature: 298.0,
                melting_temperature: 1793.0,
            }),
        ),
        (
            "tjc",
            base.with_strength(TwoRateJohnsonCook {
                yield_stress: 792.0e6,
                hardening_modulus: 510.0e6,
                hardening_exponent: 0.26,
                saturation_stress_1: 100.0e6,
                saturation_rate_1: 10.0,
                saturation_stress_2: 50.0e6,
                saturation_rate_2: 100.0,
                rate_exponent_1: 0.005,
                reference_rate_1: 1.0e-3,
                rate_exponent_2: 0.05,
                reference_rate_2: 1.0e3,
                thermal_exponent: 1.03,
                reference_temperature: 298.0,
                melting_temperature: 1793.0,
            }),
        ),
        ("ptw", base.with_strength(PrestonTonksWallace::TANTALUM)),
        ("khl", base.with_strength(KhanHuangLiang::ILLUSTRATIVE)),
        ("voce-kocks", base.with_strength(VoceKocks::ILLUSTRATIVE)),
        ("mts", base.with_strength(MechanicalThresholdStress::COPPER)),
    ];
    // JC with damage, failure, erosion and a spall cut-off, on a Mie-Grueneisen EoS.
    let failing = Material {
        failure: Failure {
            johnson_cook: Some(JohnsonCookFailure::STEEL_4340),
            erosion_plastic_strain: Some(0.8),
            pressure_cutoff: Some(-1.0e9),
            ..Failure::NONE
        },
        eos: Eos::MieGruneisen(MieGruneisen {
            reference_density: 7830.0,
            sound_speed: 4578.0,
            s1: 1.33,
            s2: 0.0,
            s3: 0.0,
            gamma0: 1.67,
            volume_correction: 0.43,
        }),
        ..base
    };
    list.push(("jc-failing", failing));
    let lagged: Vec<(&'static str, Material)> = list
        .iter()
        .map(|(name, m)| {
            (
                *name,
                Material {
                    rate_treatment: RateTreatment::Lagged,
                    ..*m
                },
            )
        })
        .collect();
    list.extend(lagged);
    let _: &Strength = &base.strength;
    list
}

fn same_state(a: &MaterialState, b: &MaterialState) -> bool {
    a.values()
        .iter()
        .zip(b.values().iter())
        .all(|(x, y)| x.to_bits() == y.to_bits())
        && a.flags == b.flags
        && a.yield_check.flow_stress.to_bits() == b.yield_check.flow_stress.to_bits()
        && a.yield_check.plastic_strain.to_bits() == b.yield_check.plastic_strain.to_bits()
        && a.yield_check.temperature.to_bits() == b.yield_check.temperature.to_bits()
}

fn same_output(a: &Result<StepOutput, UpdateError>, b: &Result<StepOutput, UpdateError>) -> bool {
    match (a, b) {
        (Ok(a), Ok(b)) => {
            a.wave_speed.to_bits() == b.wave_speed.to_bits()
                && a.plastic_increment.to_bits() == b.plastic_increment.to_bits()
                && a.yield_stress.to_bits() == b.yield_stress.to_bits()
                && a.iterations == b.iterations
        }
        (Err(a), Err(b)) => a == b,
        _ => false,
    }
}

/// A point's loading: a fixed direction, strain per step and time step.
#[derive(Clone, Copy)]
struct Loading {
    direction: [f64; 6],
    strain: f64,
    dt: f64,
}

impl Loading {
    fn new(stream: &mut Stream) -> Loading {
        Loading {
            direction: core::array::from_fn(|k| {
                let weight = if k < 3 { 1.0 } else { 0.3 };
                weight * (stream.next() - 0.5)
            }),
            strain: libm::pow(10.0, -4.0 + 1.5 * stream.next()),
            dt: libm::pow(10.0, -9.0 + 3.0 * stream.next()),
        }
    }
}

/// Each point's next input: its loading, held, reversed and resumed in turn (40 steps each),
/// with a jitter on every component and the step; now and then an inadmissible one.
fn input(
    stream: &mut Stream,
    loading: &Loading,
    point: usize,
    step: usize,
    state: &MaterialState,
) -> StepInput {
    let phase = (step / 40 + point) % 4;
    let scale = match phase {
        0 | 3 => 1.0,
        1 => 0.05,
        _ => -0.7,
    } * loading.strain;
    let strain_increment: [f64; 6] =
        core::array::from_fn(|k| scale * loading.direction[k] * (0.9 + 0.2 * stream.next()));
    let volumetric: f64 = strain_increment[..3].iter().sum();
    let mut input = StepInput {
        strain_increment,
        dt: loading.dt * (0.9 + 0.2 * stream.next()),
        relative_volume: state.relative_volume * libm::exp(volumetric),
    };
    if stream.next() < 0.003 {
        input.dt = -input.dt;
    }
    if stream.next() < 0.002 {
        input.strain_increment[1] = f64::NAN;
    }
    input
}

fn check_block<const L: usize>(name: &str, material: &Material, seed: u64, steps: usize) {
    let mut stream = Stream(seed);
    let mut single: Vec<MaterialState> = (0..L)
        .map(|p| MaterialState::initial(298.0 + 100.0 * p as f64))
        .collect();
    let mut block: [MaterialState; L] = core::array::from_fn(|p| single[p]);
    let loadings: [Loading; L] = core::array::from_fn(|_| Loading::new(&mut stream));
    let mut plastic = 0;
    let mut errors = 0;
    for step in 0..steps {
        let inputs: [StepInput; L] =
            core::array::from_fn(|p| input(&mut stream, &loadings[p], p, step, &single[p]));
        let mut outputs = [Err(UpdateError::NonFiniteInput); L];
        update_lanes(material, &mut block, &inputs, &mut outputs);
        for p in 0..L {
            let expected = update(material, &mut single[p], &inputs[p]);
            assert!(
                same_output(&outputs[p], &expected),
                "{name}, {L} lanes, step {step}, point {p}: {:?} against {:?}",
                outputs[p],
                expected
            );
            assert!(
                same_state(&block[p], &single[p]),
                "{name}, {L} lanes, step {step}, point {p}: state {:?} against {:?}",
                block[p],
                single[p]
            );
            plastic += usize::from(expected.is_ok_and(|o| o.plastic_increment > 0.0));
            errors += usize::from(expected.is_err());
        }
    }
    let failed = single
        .iter()
        .filter(|s| s.flags.contains(stoss_kernel::StateFlags::FAILED))
        .count();
    eprintln!(
        "{name} {L}: plastic {plastic} of {}, errors {errors}, failed {failed}",
        steps * L
    );
    assert!(
        plastic > steps * L / 4,
        "{name}: only {plastic} plastic updates"
    );
}

#[test]
fn a_block_update_has_the_one_point_bits_for_every_model_and_lane_count() {
    // GOAL: `update_lanes` gives every point exactly the bits `update` gives it alone: the
    //       state, the output and the error, whatever its lane-mates do (converge sooner or
    //       later, stay elastic, fail, get an inadmissible input).
    // SETUP: every strength model, both rate treatments, JC with damage, failure and a spall
    //        cut-off; 1, 3, 4 and 8 points per block, 400 steps of loading, holding,
    //        unloading and reloading with random directions, rates 1e-2 to 1e6 /s and steps
    //        1e-9 to 1e-6 s per point; now and then a negative step or a NaN strain.
    // REFERENCE: `update` on each point alone (bit equality of all thirteen state values, the
    //            flags, the stored yield check and the outputs).
    for (index, (name, material)) in materials().iter().enumerate() {
        material.validate().unwrap();
        let seed = 17 + index as u64;
        check_block::<1>(name, material, seed, 400);
        check_block::<3>(name, material, seed, 400);
        check_block::<4>(name, material, seed, 400);
        check_block::<8>(name, material, seed, 400);
    }
}

#[test]
fn a_block_of_any_length_has_the_one_point_bits() {
    // GOAL: `update_block` runs whole groups through `update_lanes` and the remainder through
    //       `update`, and reports how many points it updated.
    // SETUP: JC with damage and failure (the suite's failing material), implicit; 19 points
    //        (two groups of 8 and 3 left over) for 300 steps; slices of unequal length.
    // REFERENCE: `update` on each point alone, bit for bit; n = the shortest slice's length.
    let (_, material) = materials()
        .into_iter()
        .find(|(name, _)| *name == "jc-failing")
        .unwrap();
    let mut stream = Stream(5);
    let points = 19;
    let loadings: Vec<Loading> = (0..points).map(|_| Loading::new(&mut stream)).collect();
    let mut single: Vec<MaterialState> = (0..points)
        .map(|p| MaterialState::initial(298.0 + 10.0 * p as f64))
        .collect();
    let mut block = single.clone();
    for step in 0..300 {
        let inputs: Vec<StepInput> = (0..points)
            .map(|p| input(&mut stream, &loadings[p], p, step, &single[p]))
            .collect();
        let mut results = vec![Err(UpdateError::NonFiniteInput); points];
        assert_eq!(
            update_block(&material, &mut block, &inputs, &mut results),
            points
        );
        for p in 0..points {
            let expected = update(&material, &mut single[p], &inputs[p]);
            assert!(
                same_output(&results[p], &expected),
                "step {step}, point {p}"
            );
            assert!(same_state(&block[p], &single[p]), "step {step}, point {p}");
        }
    }
    let mut results = vec![Err(UpdateError::NonFiniteInput); 4];
    let inputs: Vec<StepInput> = (0..6)
        .map(|p| input(&mut stream, &loadings[p], p, 0, &single[p]))
        .collect();
    assert_eq!(
        update_block(&material, &mut block[..5], &inputs, &mut results),
        4
    );
}
