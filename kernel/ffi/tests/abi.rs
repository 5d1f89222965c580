//! The exported C functions, called from Rust exactly as a C host calls them: NULL pointers,
//! layout mismatches, every status code a caller can provoke, per-point failure isolation and
//! bit-exactness against the kernel's drivers.

use std::ffi::{c_char, CStr};
use std::ptr::{null, null_mut};

use stoss_kernel::damage::JohnsonCookFailure;
use stoss_kernel::drivers::{uniaxial_strain, LastRecord, UniaxialStrainLoading};
use stoss_kernel::{Material, MaterialState, StepInput};
use stoss_kernel_ffi::block::{
    StossEosModel, StossJohnsonCook, StossKhanHuangLiang, StossMechanicalThresholdStress,
    StossMieGruneisen, StossModifiedJohnsonCook, StossPrestonTonksWallace, StossRht,
    StossTwoRateJohnsonCook, StossVoceKocks, StossZerilliArmstrong,
};
use stoss_kernel_ffi::card::STOSS_CARD_MAX_LENGTH;
use stoss_kernel_ffi::section::DescribedSection;
use stoss_kernel_ffi::*;

/// Structure-of-arrays storage for `n` points.
struct Points {
    n: usize,
    strain: [Vec<f64>; 6],
    volume_in: Vec<f64>,
    stress: [Vec<f64>; 6],
    scalars: [Vec<f64>; 7],
    flags: Vec<u32>,
    wave_speed: Vec<f64>,
    failed: Vec<i32>,
    status: Vec<i32>,
    tangent: Vec<f64>,
    /// Whether the batch asks for the tangent (it does unless a test turns it off).
    with_tangent: bool,
}

impl Points {
    fn new(n: usize) -> Self {
        Self {
            n,
            strain: std::array::from_fn(|_| vec![0.0; n]),
            volume_in: vec![1.0; n],
            stress: std::array::from_fn(|_| vec![0.0; n]),
            scalars: std::array::from_fn(|_| vec![0.0; n]),
            flags: vec![0; n],
            wave_speed: vec![-1.0; n],
            failed: vec![-1; n],
            status: vec![-1; n],
            tangent: vec![0.0; 36 * n],
            with_tangent: true,
        }
    }

    fn input(&self, with_volume: bool) -> StossBatchInput {
        StossBatchInput {
            strain_increment: std::array::from_fn(|k| self.strain[k].as_ptr()),
            relative_volume: if with_volume {
                self.volume_in.as_ptr()
            } else {
                null()
            },
        }
    }

    fn state(&mut self) -> StossBatchState {
        let [eps, rate, t, d, v, e, h] = &mut self.scalars;
        StossBatchState {
            stress: {
                let mut pointers = [null_mut(); 6];
                for (k, array) in self.stress.iter_mut().enumerate() {
                    pointers[k] = array.as_mut_ptr();
                }
                pointers
            },
            plastic_strain: eps.as_mut_ptr(),
            plastic_strain_rate: rate.as_mut_ptr(),
            temperature: t.as_mut_ptr(),
            damage: d.as_mut_ptr(),
            relative_volume: v.as_mut_ptr(),
            internal_energy: e.as_mut_ptr(),
            eos_history: h.as_mut_ptr(),
            flags: self.flags.as_mut_ptr(),
        }
    }

    fn output(&mut self) -> StossBatchOutput {
        StossBatchOutput {
            wave_speed: self.wave_speed.as_mut_ptr(),
            failed: self.failed.as_mut_ptr(),
            status: self.status.as_mut_ptr(),
            tangent: if self.with_tangent {
                self.tangent.as_mut_ptr()
            } else {
                null_mut()
            },
        }
    }

    fn point(&self, i: usize) -> MaterialState {
        MaterialState {
            stress: std::array::from_fn(|k| self.stress[k][i]),
            plastic_strain: self.scalars[0][i],
            plastic_strain_rate: self.scalars[1][i],
            temperature: self.scalars[2][i],
            damage: self.scalars[3][i],
            relative_volume: self.scalars[4][i],
            internal_energy: self.scalars[5][i],
            eos_history: self.scalars[6][i],
            flags: stoss_kernel::StateFlags(self.flags[i]),
            yield_check: stoss_kernel::YieldCheck::NONE,
        }
    }

    fn init(&mut self, block: &StossMaterialBlock) {
        let state = self.state();
        // SAFETY: every array holds `n` elements.
        let status = unsafe { stoss_state_init(block, self.n, &state, null_mut(), 0) };
        assert_eq!(status, StossStatus::Ok);
    }

    fn update(&mut self, block: &StossMaterialBlock, dt: f64, with_volume: bool) -> Outcome {
        let input = self.input(with_volume);
        let state = self.state();
        let output = self.output();
        let mut first_failure = usize::MAX;
        let mut message = [0 as c_char; 256];
        // SAFETY: every array holds `n` elements (36 n for the tangent).
        let status = unsafe {
            stoss_update_batch(
                block,
                self.n,
                dt,
                &input,
                &state,
                &output,
                &mut first_failure,
                message.as_mut_ptr(),
                message.len(),
            )
        };
        Outcome {
            status,
            first_failure,
            message: text(&message),
        }
    }
}

struct Outcome {
    status: StossStatus,
    first_failure: usize,
    message: String,
}

fn text(buffer: &[c_char]) -> String {
    // SAFETY: the library always NUL-terminates within the capacity.
    unsafe { CStr::from_ptr(buffer.as_ptr()) }
        .to_str()
        .unwrap()
        .to_owned()
}

fn defaults() -> StossMaterialBlock {
    let mut block = StossMaterialBlock::default();
    // SAFETY: `block` is a valid, writable block.
    assert_eq!(
        unsafe { stoss_material_defaults_4340(&mut block) },
        StossStatus::Ok
    );
    block
}

/// The card of a valid block through `stoss_material_to_card`, and its length.
fn write_card(block: &StossMaterialBlock) -> ([f64; STOSS_CARD_MAX_LENGTH], usize) {
    let mut card = [0.0; STOSS_CARD_MAX_LENGTH];
    let mut length = 0;
    // SAFETY: `card` holds STOSS_CARD_MAX_LENGTH doubles.
    let status = unsafe {
        stoss_material_to_card(
            block,
            card.as_mut_ptr(),
            card.len(),
            &mut length,
            null_mut(),
            0,
        )
    };
    assert_eq!(status, StossStatus::Ok);
    (card, length)
}

/// The block of a valid card through `stoss_material_from_card`.
fn read_card(card: &[f64]) -> StossMaterialBlock {
    let mut parsed = StossMaterialBlock::default();
    // SAFETY: `card` holds `card.len()` doubles; `parsed` is writable.
    let status =
        unsafe { stoss_material_from_card(card.as_ptr(), card.len(), &mut parsed, null_mut(), 0) };
    assert_eq!(status, StossStatus::Ok);
    parsed
}

fn validate(block: *const StossMaterialBlock) -> (StossStatus, String) {
    let mut message = [0 as c_char; 256];
    // SAFETY: the message buffer holds 256 bytes; `block` is NULL or a valid block.
    let status = unsafe { stoss_material_validate(block, message.as_mut_ptr(), message.len()) };
    (status, text(&message))
}

#[test]
fn status_names_are_static_c_strings() {
    for status in StossStatus::ALL {
        // SAFETY: the returned pointer is a static NUL-terminated string.
        let name = unsafe { CStr::from_ptr(stoss_status_name(status as i32)) };
        assert_eq!(name.to_str().unwrap(), status.name());
    }
    // SAFETY: as above.
    let unknown = unsafe { CStr::from_ptr(stoss_status_name(1000)) };
    assert_eq!(unknown.to_str().unwrap(), "STOSS_STATUS_UNKNOWN");
    assert_eq!(stoss_layout_version(), STOSS_LAYOUT_VERSION);
    assert_eq!(
        stoss_material_block_size() as usize,
        std::mem::size_of::<StossMaterialBlock>()
    );
}

#[test]
fn null_pointers_are_reported_not_dereferenced() {
    let (status, message) = validate(null());
    assert_eq!(status, StossStatus::NullPointer);
    assert!(message.starts_with("block:"), "{message}");
    // SAFETY: NULL is rejected before use.
    assert_eq!(
        unsafe { stoss_material_defaults_4340(null_mut()) },
        StossStatus::NullPointer
    );

    let block = defaults();
    let mut points = Points::new(2);
    let input = points.input(false);
    let mut state = points.state();
    let mut message = [0 as c_char; 256];
    // NULL input struct, NULL state struct, NULL array inside the state or the input.
    for case in 0..4 {
        let mut input = input;
        if case == 2 {
            state.temperature = null_mut();
        }
        if case == 3 {
            state.temperature = points.scalars[2].as_mut_ptr();
            input.strain_increment[4] = null();
        }
        let input_pointer: *const StossBatchInput = if case == 0 { null() } else { &input };
        let state_pointer: *const StossBatchState = if case == 1 { null() } else { &state };
        // SAFETY: all non-NULL arrays hold 2 elements.
        let status = unsafe {
            stoss_update_batch(
                &block,
                2,
                1e-6,
                input_pointer,
                state_pointer,
                null(),
                null_mut(),
                message.as_mut_ptr(),
                message.len(),
            )
        };
        assert_eq!(status, StossStatus::NullPointer, "case {case}");
        let expected = [
            "input:",
            "state:",
            "state.temperature:",
            "input.strain_increment[4] (yz):",
        ];
        assert!(
            text(&message).starts_with(expected[case]),
            "{}",
            text(&message)
        );
    }
    // NULL message buffer is allowed.
    // SAFETY: NULL block and message are both handled.
    let status = unsafe { stoss_material_validate(null(), null_mut(), 100) };
    assert_eq!(status, StossStatus::NullPointer);
}

#[test]
fn layout_version_and_size_are_checked_before_the_block_is_read() {
    let mut block = defaults();
    block.layout_version = 1;
    let (status, message) = validate(&block);
    assert_eq!(status, StossStatus::BadLayoutVersion);
    assert!(
        message.contains(&format!("expects {STOSS_LAYOUT_VERSION}")),
        "{message}"
    );

    let mut block = defaults();
    block.struct_size = 16;
    assert_eq!(validate(&block).0, StossStatus::BadStructSize);

    // A host with an older, smaller block: only its 8-byte header is ever read.
    let header: [u64; 1] = [u64::from(99_u32) | (u64::from(8_u32) << 32)];
    let pointer = header.as_ptr().cast::<StossMaterialBlock>();
    assert_eq!(validate(pointer).0, StossStatus::BadLayoutVersion);
}

#[test]
fn invalid_parameters_name_the_field() {
    let mut block = defaults();
    block.strength.johnson_cook.hardening_exponent = 5.0;
    let (status, message) = validate(&block);
    assert_eq!(status, StossStatus::InvalidParameter);
    assert_eq!(
        message,
        "strength.johnson_cook: hardening_exponent: 5 is outside [0, 2]"
    );
    // The update refuses the same block with the same message.
    let mut points = Points::new(1);
    let outcome = points.update(&block, 1e-6, false);
    assert_eq!(outcome.status, StossStatus::InvalidParameter);
    assert_eq!(outcome.message, message);
}

#[test]
fn zero_points_is_its_own_status() {
    let block = defaults();
    let mut points = Points::new(1);
    let input = points.input(false);
    let state = points.state();
    // SAFETY: n = 0 touches no array.
    let status = unsafe {
        stoss_update_batch(
            &block,
            0,
            1e-6,
            &input,
            &state,
            null(),
            null_mut(),
            null_mut(),
            0,
        )
    };
    assert_eq!(status, StossStatus::ZeroPoints);
    // SAFETY: as above.
    let status = unsafe { stoss_state_init(&block, 0, &state, null_mut(), 0) };
    assert_eq!(status, StossStatus::ZeroPoints);
}

#[test]
fn a_failing_point_keeps_its_state_and_the_others_proceed() {
    let block = defaults();
    let mut points = Points::new(4);
    points.init(&block);
    for i in 0..4 {
        points.strain[0][i] = -1e-3;
    }
    let outcome = points.update(&block, 1e-7, false);
    assert_eq!(outcome.status, StossStatus::Ok);
    assert_eq!(outcome.first_failure, 4);
    assert_eq!(outcome.message, "");
    let before: Vec<MaterialState> = (0..4).map(|i| points.point(i)).collect();

    points.strain[1][2] = f64::NAN;
    points.strain[0][3] = f64::INFINITY;
    let outcome = points.update(&block, 1e-7, false);
    assert_eq!(outcome.status, StossStatus::NonFiniteInput);
    assert_eq!(outcome.first_failure, 2);
    assert_eq!(
        outcome.message,
        "point 2: strain increment, dt or relative volume is not finite"
    );
    assert_eq!(points.status, vec![0, 0, 5, 5]);
    assert_eq!(points.point(2), before[2]);
    assert_eq!(points.point(3), before[3]);
    assert_ne!(points.point(0), before[0]);
    assert_eq!(points.point(0), points.point(1));
}

#[test]
fn time_step_volume_state_and_result_errors_have_their_codes() {
    let block = defaults();
    let mut points = Points::new(2);
    points.init(&block);
    points.strain[0][0] = -1e-4;
    points.strain[0][1] = -1e-4;
    for (dt, code) in [(-1e-6, 6), (0.0, 6), (f64::NAN, 5)] {
        let outcome = points.update(&block, dt, false);
        assert_eq!(outcome.status as i32, code, "dt = {dt}");
        assert_eq!(outcome.first_failure, 0);
        assert_eq!(points.status, vec![code, code]);
    }

    points.volume_in = vec![1.0, -0.5];
    let outcome = points.update(&block, 1e-6, true);
    assert_eq!(outcome.status, StossStatus::NonPositiveVolume);
    assert_eq!(outcome.first_failure, 1);
    assert_eq!(points.status, vec![0, 7]);

    points.scalars[2][0] = f64::NAN; // temperature of point 0
    let outcome = points.update(&block, 1e-6, false);
    assert_eq!(outcome.status, StossStatus::NonFiniteState);
    assert_eq!(outcome.first_failure, 0);

    // Mie-Grüneisen beyond its limiting compression (S1 = 2: mu = 1, V = 1/2) overflows.
    let mut block = defaults();
    block.eos_model = StossEosModel::MieGruneisen as i32;
    block.eos.mie_gruneisen = StossMieGruneisen {
        reference_density: 7830.0,
        sound_speed: 4500.0,
        s1: 2.0,
        s2: 0.0,
        s3: 0.0,
        gamma0: 2.0,
        volume_correction: 0.0,
    };
    let mut points = Points::new(1);
    points.init(&block);
    points.volume_in = vec![0.5];
    let outcome = points.update(&block, 1e-6, true);
    assert_eq!(outcome.status, StossStatus::NonFiniteResult);
    assert_eq!(points.point(0), MaterialState::initial(298.0));
}

#[test]
fn misaligned_arrays_are_rejected() {
    let block = defaults();
    let mut points = Points::new(2);
    let mut input = points.input(false);
    let storage = [0.0_f64; 4];
    // SAFETY: only the address is formed (one byte into `storage`), never dereferenced.
    input.strain_increment[0] = unsafe { storage.as_ptr().cast::<u8>().add(1).cast() };
    let state = points.state();
    let mut message = [0 as c_char; 128];
    // SAFETY: the misaligned array is rejected before any access.
    let status = unsafe {
        stoss_update_batch(
            &block,
            2,
            1e-6,
            &input,
            &state,
            null(),
            null_mut(),
            message.as_mut_ptr(),
            message.len(),
        )
    };
    assert_eq!(status, StossStatus::MisalignedPointer);
    assert!(text(&message).starts_with("input.strain_increment[0] (xx):"));
}

#[test]
fn batch_reproduces_the_driver_bit_for_bit_for_every_point() {
    // Two points on opposite uniaxial-strain paths in one batch; each must equal the kernel's
    // driver run on its own. The block is built through the ABI, the reference from kernel
    // structs, so the block conversion is checked too.
    let mut block = defaults();
    block.failure.johnson_cook_enabled = 1;
    let mut material = Material::STEEL_4340;
    material.failure.johnson_cook = Some(JohnsonCookFailure::STEEL_4340);

    let steps = 300;
    let rate = 1.0e4;
    let finals = [0.3, -0.3];
    let mut points = Points::new(2);
    points.init(&block);
    let increment = finals[0] / f64::from(steps);
    let dt = increment.abs() / rate;
    points.strain[0] = vec![increment, -increment];
    for _ in 0..steps {
        let outcome = points.update(&block, dt, false);
        assert_eq!(outcome.status, StossStatus::Ok, "{}", outcome.message);
    }
    for (i, final_strain) in finals.iter().enumerate() {
        let mut reference = MaterialState::initial(298.0);
        let loading = UniaxialStrainLoading {
            strain_rate: rate,
            final_strain: *final_strain,
            steps,
        };
        let mut sink = LastRecord::default();
        uniaxial_strain(&material, &mut reference, &loading, &mut sink).unwrap();
        assert_eq!(points.point(i), reference, "point {i}");
        assert_eq!(points.wave_speed[i], sink.last.unwrap().wave_speed);
    }
    // The tension point failed (JC damage), the compression point did not.
    assert_eq!(points.failed, vec![STOSS_FAILED_DAMAGE, 0]);
    // Failed: no shear stiffness left in the tangent.
    assert_eq!(points.tangent[3 * 6 + 3], 0.0);
    assert!(points.tangent[36 + 3 * 6 + 3] > 0.0);
}

#[test]
#[allow(clippy::needless_range_loop)]
fn a_batch_without_the_tangent_goes_through_the_group_update_bit_for_bit() {
    // GOAL: without a tangent the batch advances its points LANES at a time through the
    //       kernel's group update (`PointModel::update_lanes`); every point's state, wave
    //       speed, failure code and status are those of the one-point update.
    // SETUP: JC 4340 with JC damage; 21 points (two groups of 8, then 5 one at a time):
    //        compression and tension at 1e2-1e5 /s, point 4 held elastic, a NaN strain on
    //        point 9 at step 40; 200 steps, the volume integrated by the ABI.
    // REFERENCE: `stoss_kernel::update` on each point alone, with the ABI's volume rule
    //            `V1 = V0 exp(tr deps)` and no stored yield check (the ABI's state has none).
    let mut block = defaults();
    block.failure.johnson_cook_enabled = 1;
    let mut material = Material::STEEL_4340;
    material.failure.johnson_cook = Some(JohnsonCookFailure::STEEL_4340);
    let n = 21;
    let mut points = Points::new(n);
    points.with_tangent = false;
    points.init(&block);
    let mut reference: Vec<MaterialState> = (0..n).map(|i| points.point(i)).collect();
    let dt = 1.0e-8;
    let axial = |i: usize| -> f64 {
        if i == 4 {
            1.0e-9
        } else {
            let sign = if i % 3 == 0 { 1.0 } else { -1.0 };
            let x = i as f64 / n as f64;
            sign * 1.0e-6 * (1.0 + 999.0 * x * x)
        }
    };
    let mut failed = 0;
    for step in 0..200 {
        for i in 0..n {
            points.strain[0][i] = if i == 9 && step == 40 {
                f64::NAN
            } else {
                axial(i)
            };
            points.strain[1][i] = -0.3 * axial(i);
        }
        points.update(&block, dt, false);
        for i in 0..n {
            let strain_increment = std::array::from_fn(|k| points.strain[k][i]);
            let volumetric: f64 = (0..3).map(|k| points.strain[k][i]).sum();
            let input = StepInput {
                strain_increment,
                dt,
                relative_volume: reference[i].relative_volume * stoss_kernel::math::exp(volumetric),
            };
            reference[i].yield_check = stoss_kernel::YieldCheck::NONE;
            let expected = stoss_kernel::update(&material, &mut reference[i], &input);
            reference[i].yield_check = stoss_kernel::YieldCheck::NONE;
            assert_eq!(points.point(i), reference[i], "step {step}, point {i}");
            match expected {
                Ok(output) => {
                    assert_eq!(points.status[i], 0, "step {step}, point {i}");
                    assert_eq!(
                        points.wave_speed[i].to_bits(),
                        output.wave_speed.to_bits(),
                        "step {step}, point {i}"
                    );
                }
                Err(error) => {
                    assert_eq!(points.status[i], StossStatus::from(error) as i32);
                    failed += 1;
                }
            }
        }
    }
    assert_eq!(failed, 1, "the NaN step alone is refused");
    assert!(points.failed.contains(&STOSS_FAILED_DAMAGE));
}

#[test]
fn cards_round_trip_and_report_buffer_sizes() {
    let block = defaults();
    let mut card = [0.0; STOSS_CARD_MAX_LENGTH];
    let mut length = 0;
    let mut message = [0 as c_char; 128];
    // SAFETY: `card` holds 10 (< needed) doubles.
    let status = unsafe {
        stoss_material_to_card(
            &block,
            card.as_mut_ptr(),
            10,
            &mut length,
            message.as_mut_ptr(),
            message.len(),
        )
    };
    assert_eq!(status, StossStatus::BufferTooSmall);
    assert_eq!(length, 41);
    assert_eq!(card[0], 0.0);
    let (card, length) = write_card(&block);
    let parsed = read_card(&card[..length]);
    // Same material (switched-off families, e.g. the disabled JC failure constants, are not
    // carried by the card).
    assert_eq!(parsed.to_material(), block.to_material());

    let (mut bulk, mut shear, mut wave) = (0.0, 0.0, 0.0);
    // SAFETY: valid block and outputs.
    let status = unsafe {
        stoss_material_elastic_moduli(&block, &mut bulk, &mut shear, &mut wave, null_mut(), 0)
    };
    assert_eq!(status, StossStatus::Ok);
    assert_eq!((bulk, shear), (card[3], card[2]));
    let expected = stoss_kernel::math::sqrt((159.0e9 + 4.0 * 81.8e9 / 3.0) / 7830.0);
    assert_eq!(wave, expected);
}

#[test]
fn adapters_check_their_dimensions() {
    let block = defaults();
    let mut card = [0.0; STOSS_CARD_MAX_LENGTH];
    let mut length = 0;
    // SAFETY: `card` holds STOSS_CARD_MAX_LENGTH doubles.
    unsafe {
        stoss_material_to_card(
            &block,
            card.as_mut_ptr(),
            card.len(),
            &mut length,
            null_mut(),
            0,
        )
    };
    let eps = [0.0; 6];
    let mut sig = [0.0; 6];
    let mut hsv = [0.0; 8];
    let mut message = [0 as c_char; 128];
    // SAFETY: arrays sized for nlq = 1 and nhv = 7 (< 8: rejected before access).
    let status = unsafe {
        stoss_lsdyna_umat(
            card.as_ptr(),
            length,
            1,
            1e-6,
            eps.as_ptr(),
            sig.as_mut_ptr(),
            hsv.as_mut_ptr(),
            7,
            null_mut(),
            null_mut(),
            null_mut(),
            null_mut(),
            message.as_mut_ptr(),
            message.len(),
        )
    };
    assert_eq!(status, StossStatus::BufferTooSmall);
    assert!(text(&message).starts_with("nhv: 7"));

    let old = [0.0; 8];
    let mut new = [0.0; 8];
    let energy_old = [0.0];
    let mut energy_new = [0.0];
    for (ndir, nshr, nstatev, expected) in [
        (2, 1, 8, StossStatus::InvalidArgument),
        (3, 2, 8, StossStatus::InvalidArgument),
        (3, 3, 7, StossStatus::BufferTooSmall),
        (3, 3, 8, StossStatus::Ok),
    ] {
        // SAFETY: arrays sized for nblock = 1, 6 components, 8 state variables.
        let status = unsafe {
            stoss_abaqus_vumat(
                card.as_ptr(),
                length,
                1,
                ndir,
                nshr,
                nstatev,
                0.0,
                1e-3,
                1e-6,
                eps.as_ptr(),
                eps.as_ptr(),
                old.as_ptr(),
                energy_old.as_ptr(),
                sig.as_mut_ptr(),
                new.as_mut_ptr(),
                energy_new.as_mut_ptr(),
                null_mut(),
                null_mut(),
                null_mut(),
                null_mut(),
                0,
            )
        };
        assert_eq!(
            status, expected,
            "ndir {ndir} nshr {nshr} nstatev {nstatev}"
        );
    }
    // The successful call initialised the point.
    assert_eq!(new[4], 1.0);
    assert_eq!(new[2], 298.0);
}

#[test]
fn concurrent_calls_on_disjoint_points_equal_serial_calls() {
    // Reentrancy: no global state, so threads sharing one block give the serial bits.
    let mut block = defaults();
    block.failure.johnson_cook_enabled = 1;
    let run = |sign: f64| {
        let mut points = Points::new(3);
        points.init(&block);
        points.strain[0] = vec![sign * 1e-3, sign * 2e-3, sign * 5e-4];
        points.strain[3] = vec![2e-4, -1e-4, 3e-4];
        for _ in 0..200 {
            let outcome = points.update(&block, 1e-7, false);
            assert_eq!(outcome.status, StossStatus::Ok);
        }
        (0..3).map(|i| points.point(i)).collect::<Vec<_>>()
    };
    let serial: Vec<_> = [1.0, -1.0, 0.5, -0.5].iter().map(|s| run(*s)).collect();
    let parallel: Vec<_> = std::thread::scope(|scope| {
        let handles: Vec<_> = [1.0, -1.0, 0.5, -0.5]
            .iter()
            .map(|s| scope.spawn(move || run(*s)))
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    assert_eq!(serial, parallel);
}

#[test]
fn vumat_plane_strain_equals_3d_without_out_of_plane_shear() {
    let block = defaults();
    let mut card = [0.0; STOSS_CARD_MAX_LENGTH];
    let mut length = 0;
    // SAFETY: `card` holds STOSS_CARD_MAX_LENGTH doubles.
    unsafe {
        stoss_material_to_card(
            &block,
            card.as_mut_ptr(),
            card.len(),
            &mut length,
            null_mut(),
            0,
        )
    };
    let run = |nshr: usize| {
        let components = 3 + nshr;
        let strain: Vec<f64> = [-2e-3, 1e-3, 0.0, 1.5e-3, 0.0, 0.0][..components].to_vec();
        let mut stress = vec![0.0; components];
        let mut state = vec![0.0; 8];
        let mut energy = [0.0];
        for step in 1..=50 {
            let (mut stress_new, mut state_new, mut energy_new) =
                (vec![0.0; components], vec![0.0; 8], [0.0]);
            let time = f64::from(step) * 1e-7;
            // SAFETY: arrays sized for nblock = 1, `components` components, 8 states.
            let status = unsafe {
                stoss_abaqus_vumat(
                    card.as_ptr(),
                    length,
                    1,
                    3,
                    nshr,
                    8,
                    time,
                    time,
                    1e-7,
                    strain.as_ptr(),
                    stress.as_ptr(),
                    state.as_ptr(),
                    energy.as_ptr(),
                    stress_new.as_mut_ptr(),
                    state_new.as_mut_ptr(),
                    energy_new.as_mut_ptr(),
                    null_mut(),
                    null_mut(),
                    null_mut(),
                    null_mut(),
                    0,
                )
            };
            assert_eq!(status, StossStatus::Ok);
            (stress, state, energy) = (stress_new, state_new, energy_new);
        }
        (stress, state, energy)
    };
    let (plane, plane_state, plane_energy) = run(1);
    let (solid, solid_state, solid_energy) = run(3);
    assert_eq!(&solid[..4], &plane[..]);
    assert_eq!(solid[4..], [0.0, 0.0]);
    assert_eq!(plane_state, solid_state);
    assert_eq!(plane_energy, solid_energy);
    assert!(plane_state[0] > 0.0, "the path is plastic");
}

/// One `stoss_abaqus_vumat` call on a 3D block of `nblock` points, `nstatev` state variables
/// (column-major, as Abaqus passes them); returns the new stress, states, energies, wave
/// speeds and statuses.
#[allow(clippy::type_complexity)]
fn vumat_block(
    card: &[f64],
    nblock: usize,
    nstatev: usize,
    time: f64,
    dt: f64,
    strain: &[f64],
    old: (&[f64], &[f64], &[f64]),
) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>, Vec<i32>) {
    let (stress, state, energy) = old;
    let mut stress_new = vec![0.0; 6 * nblock];
    let mut state_new = vec![0.0; nstatev * nblock];
    let mut energy_new = vec![0.0; nblock];
    let mut wave_speed = vec![0.0; nblock];
    let mut status = vec![-1; nblock];
    // SAFETY: arrays sized for `nblock` points, 6 components and `nstatev` states.
    unsafe {
        stoss_abaqus_vumat(
            card.as_ptr(),
            card.len(),
            nblock,
            3,
            3,
            nstatev,
            time,
            time,
            dt,
            strain.as_ptr(),
            stress.as_ptr(),
            state.as_ptr(),
            energy.as_ptr(),
            stress_new.as_mut_ptr(),
            state_new.as_mut_ptr(),
            energy_new.as_mut_ptr(),
            wave_speed.as_mut_ptr(),
            status.as_mut_ptr(),
            null_mut(),
            null_mut(),
            0,
        )
    };
    (stress_new, state_new, energy_new, wave_speed, status)
}

#[test]
fn a_vumat_block_equals_its_points_called_one_at_a_time() {
    // GOAL: a VUMAT block advances its points LANES at a time through the kernel's group
    //       update, and every point's outputs are those of a call with that point alone (one
    //       point always takes the one-point path); a point whose step fails keeps its old
    //       values beside lane-mates that proceed; the host's extra state variables are
    //       carried.
    // SETUP: 4340 JC card; 19 points (two groups of 8 and 3 one at a time), 10 state
    //        variables (2 the host's); 120 steps of 1e-8 s, compression and tension at
    //        5e3-5e4 /s with shear, point 5 nearly elastic, a NaN strain on point 10 at step 30.
    // REFERENCE: 19 single-point calls on the same inputs, bit for bit.
    let (card, length) = write_card(&defaults());
    let card = &card[..length];
    let (n, nstatev, dt) = (19, 10, 1.0e-8);
    let mut stress = vec![0.0; 6 * n];
    let mut state: Vec<f64> = (0..nstatev * n)
        .map(|v| if v >= 8 * n { v as f64 } else { 0.0 })
        .collect();
    let mut energy = vec![0.0; n];
    let mut singles: Vec<(Vec<f64>, Vec<f64>, Vec<f64>)> = (0..n)
        .map(|i| {
            let state = (0..nstatev).map(|j| state[i + n * j]).collect();
            (vec![0.0; 6], state, vec![0.0])
        })
        .collect();
    let mut refused = 0;
    for step in 1..=120 {
        let time = f64::from(step) * dt;
        let mut strain = vec![0.0; 6 * n];
        for i in 0..n {
            let x = i as f64 / n as f64;
            let sign = if i % 3 == 0 { 1.0 } else { -1.0 };
            let rate = if i == 5 {
                1.0e-9
            } else {
                5.0e-5 * (1.0 + 9.0 * x * x)
            };
            strain[i] = sign * rate;
            strain[i + n] = -0.4 * sign * rate;
            strain[i + 3 * n] = 0.3 * rate;
            if i == 10 && step == 30 {
                strain[i] = f64::NAN;
            }
        }
        let (stress_new, state_new, energy_new, wave, status) = vumat_block(
            card,
            n,
            nstatev,
            time,
            dt,
            &strain,
            (&stress, &state, &energy),
        );
        for (i, single) in singles.iter_mut().enumerate() {
            let point_strain: Vec<f64> = (0..6).map(|k| strain[i + n * k]).collect();
            let (s1, st1, e1, w1, status1) = vumat_block(
                card,
                1,
                nstatev,
                time,
                dt,
                &point_strain,
                (&single.0, &single.1, &single.2),
            );
            assert_eq!(status[i], status1[0], "step {step}, point {i}");
            for k in 0..6 {
                assert_eq!(
                    stress_new[i + n * k].to_bits(),
                    s1[k].to_bits(),
                    "step {step}, point {i}"
                );
            }
            for j in 0..nstatev {
                assert_eq!(
                    state_new[i + n * j].to_bits(),
                    st1[j].to_bits(),
                    "step {step}, point {i}"
                );
            }
            assert_eq!(energy_new[i].to_bits(), e1[0].to_bits());
            if status1[0] == 0 {
                assert_eq!(wave[i].to_bits(), w1[0].to_bits());
            } else {
                refused += 1;
            }
            *single = (s1, st1, e1);
        }
        (stress, state, energy) = (stress_new, state_new, energy_new);
    }
    assert_eq!(refused, 1, "the NaN step alone is refused");
    assert!(
        (0..n).filter(|&i| state[i] > 0.0).count() >= n - 2,
        "the paths are plastic"
    );
    assert_eq!(
        state[8 * n + 3],
        (8 * n + 3) as f64,
        "the host's variables are carried"
    );
}

fn concrete() -> StossMaterialBlock {
    let mut block = StossMaterialBlock::default();
    // SAFETY: `block` is a valid, writable block.
    assert_eq!(
        unsafe { stoss_material_defaults_hpc92(&mut block) },
        StossStatus::Ok
    );
    block
}

#[test]
fn rht_concrete_runs_through_the_batch_bit_for_bit_and_round_trips_its_card() {
    // GOAL: RHT concrete (layout 3) through the same entry points as the metals: the batch
    //       equals the kernel's uniaxial-strain driver bit for bit, from the P-alpha initial
    //       state that stoss_state_init gives; the card carries it exactly.
    // SETUP: the library's HPC 92 MPa defaults; one point crushed to -5 %, one pulled to
    //        +0.2 % (it fails at the hydro tensile limit), 250 steps at 1e3 /s.
    // REFERENCE: stoss_kernel::drivers::uniaxial_strain on RhtMaterial::HPC_92MPA.
    use stoss_kernel::rht::RhtMaterial;
    let block = concrete();
    assert_eq!(validate(&block).0, StossStatus::Ok);
    assert_eq!(block.to_rht().unwrap(), RhtMaterial::HPC_92MPA);
    let steps = 250;
    let rate = 1.0e3;
    let finals = [-0.05, 0.002];
    for final_strain in finals {
        let mut points = Points::new(1);
        points.init(&block);
        assert_eq!(
            points.point(0),
            RhtMaterial::HPC_92MPA.initial_state(293.0),
            "initial state"
        );
        let increment = final_strain / f64::from(steps);
        let dt = increment.abs() / rate;
        points.strain[0] = vec![increment];
        for _ in 0..steps {
            let outcome = points.update(&block, dt, false);
            assert_eq!(outcome.status, StossStatus::Ok, "{}", outcome.message);
        }
        let mut reference = RhtMaterial::HPC_92MPA.initial_state(293.0);
        let loading = UniaxialStrainLoading {
            strain_rate: rate,
            final_strain,
            steps,
        };
        let mut sink = LastRecord::default();
        uniaxial_strain(&RhtMaterial::HPC_92MPA, &mut reference, &loading, &mut sink).unwrap();
        assert_eq!(points.point(0), reference, "final strain {final_strain}");
        assert_eq!(points.wave_speed[0], sink.last.unwrap().wave_speed);
        let failed = if final_strain > 0.0 {
            STOSS_FAILED_DAMAGE
        } else {
            0
        };
        assert_eq!(points.failed, vec![failed], "final strain {final_strain}");
    }

    let (card, length) = write_card(&block);
    assert_eq!(length, 41 + 11, "P1..P41 and the P-alpha section");
    assert_eq!(card[0], f64::from(STOSS_LAYOUT_VERSION));
    assert_eq!(card[6], 7.0, "strength code RHT");
    assert_eq!(card[20], 92.0e6, "f'c at P21");
    let parsed = read_card(&card[..length]);
    assert_eq!(parsed.to_rht().unwrap(), RhtMaterial::HPC_92MPA);
}

#[test]
fn rht_blocks_refuse_what_concrete_does_not_have() {
    // GOAL: metal-only options on an RHT block are errors naming the field, not ignored.
    // SETUP: the HPC defaults with, in turn, adiabatic heating, the lagged rate, JC failure
    //        and the pressure cut-off switched on, a bad RHT code and a negative f'c.
    // REFERENCE: INVALID_PARAMETER and the field's name in the message.
    type Spoil = fn(&mut StossMaterialBlock);
    let cases: [(&str, Spoil); 6] = [
        ("heating_model", |b| b.heating_model = 2),
        ("rate_treatment", |b| b.rate_treatment = 2),
        ("failure.johnson_cook_enabled", |b| {
            b.failure.johnson_cook_enabled = 1
        }),
        ("failure.pressure_cutoff_enabled", |b| {
            b.failure.pressure_cutoff_enabled = 1
        }),
        ("strength.rht.meridian", |b| b.strength.rht.meridian = 9),
        ("compressive_strength", |b| {
            b.strength.rht.compressive_strength = -1.0
        }),
    ];
    for (field, spoil) in cases {
        let mut block = concrete();
        spoil(&mut block);
        let (status, message) = validate(&block);
        assert_eq!(status, StossStatus::InvalidParameter, "{field}: {message}");
        assert!(message.contains(field), "{field}: {message}");
    }
}

fn kc_concrete() -> StossMaterialBlock {
    let mut block = StossMaterialBlock::default();
    // SAFETY: `block` is a valid, writable block.
    assert_eq!(
        unsafe { stoss_material_defaults_kc100(&mut block) },
        StossStatus::Ok
    );
    block
}

#[test]
fn kc_concrete_runs_through_the_batch_bit_for_bit_and_round_trips_its_card() {
    // GOAL: K&C concrete (layout 5) through the same entry points as RHT and the metals: the
    //       batch equals the kernel's uniaxial-strain driver bit for bit from the state
    //       stoss_state_init gives; the card carries it exactly.
    // SETUP: the library's HPC 100 MPa defaults (tabulated EoS, CEB-FIP rates); one point
    //        crushed to -3 %, one pulled to +0.05 % (past the tensile peak), 250 steps at
    //        1e2 /s.
    // REFERENCE: stoss_kernel::drivers::uniaxial_strain on KcMaterial::HPC_100MPA_FOI.
    use stoss_kernel::kc::KcMaterial;
    let material = KcMaterial::HPC_100MPA_FOI;
    let block = kc_concrete();
    assert_eq!(validate(&block).0, StossStatus::Ok);
    assert_eq!(block.to_kc().unwrap(), material);
    let steps = 250;
    let rate = 1.0e2;
    for final_strain in [-0.03, 0.0005] {
        let mut points = Points::new(1);
        points.init(&block);
        assert_eq!(
            points.point(0),
            material.initial_state(293.0),
            "initial state"
        );
        let increment = final_strain / f64::from(steps);
        let dt = increment.abs() / rate;
        points.strain[0] = vec![increment];
        for _ in 0..steps {
            let outcome = points.update(&block, dt, false);
            assert_eq!(outcome.status, StossStatus::Ok, "{}", outcome.message);
        }
        let mut reference = material.initial_state(293.0);
        let loading = UniaxialStrainLoading {
            strain_rate: rate,
            final_strain,
            steps,
        };
        let mut sink = LastRecord::default();
        uniaxial_strain(&material, &mut reference, &loading, &mut sink).unwrap();
        assert_eq!(points.point(0), reference, "final strain {final_strain}");
        assert_eq!(points.wave_speed[0], sink.last.unwrap().wave_speed);
        assert!(reference.plastic_strain > 0.0, "{final_strain}: it yields");
    }

    let (card, length) = write_card(&block);
    let stoss_kernel::eos::Eos::TabulatedCompaction(eos) = material.eos else {
        panic!("K&C's EoS is tabulated");
    };
    let table = 1 + 3 * eos.points().len();
    let damage = 1 + 2 * material.parameters.damage.used();
    assert_eq!(
        length,
        41 + table + damage,
        "P1..P41, the EoS and the damage table"
    );
    assert_eq!(card[0], f64::from(STOSS_LAYOUT_VERSION));
    assert_eq!(card[6], 8.0, "strength code K&C");
    assert_eq!(card[28], 100.0e6, "fc at P29");
    let parsed = read_card(&card[..length]);
    assert_eq!(parsed.to_kc().unwrap(), material);
    assert_eq!(parsed, block);
}

#[test]
fn kc_constants_follow_the_kernel_descriptor_in_block_and_card() {
    // GOAL: the block's and the card's K&C scalars are the kernel's described constants in
    //       the descriptor's order (the shear modulus in the block's common field), so a
    //       constant added to the family reaches both without an edit here.
    // SETUP: the HPC defaults with a distinct value in every described constant, set by
    //        name through the kernel's descriptor.
    // REFERENCE: KcParameters::PARAMETERS.
    use stoss_kernel::kc::{KcMaterial, KcParameters};
    use stoss_kernel::parameters::Constants;
    use stoss_kernel_ffi::export::from_kc;
    let mut material = KcMaterial::HPC_100MPA_FOI;
    // Values that keep the material valid: each constant scaled by a distinct factor.
    for (i, parameter) in KcParameters::PARAMETERS.iter().enumerate() {
        let value = material.parameters.get(parameter.name).unwrap();
        let scaled = value * (1.0 + 0.001 * (i as f64 + 1.0));
        material.parameters.set(parameter.name, scaled).unwrap();
    }
    let (block, dropped) = from_kc(&material, 293.0, 880.0).unwrap();
    assert!(!dropped);
    assert_eq!(block.shear_modulus, material.parameters.shear_modulus);
    let section: Vec<&str> = KcParameters::PARAMETERS
        .iter()
        .map(|p| p.name)
        .filter(|name| *name != "shear_modulus")
        .collect();
    assert_eq!(section.len(), stoss_kernel_ffi::block::KC_CONSTANTS);
    for (slot, name) in section.iter().enumerate() {
        let value = material.parameters.get(name).unwrap();
        assert_eq!(block.strength.kc.constants[slot], value, "{name}");
    }
    assert!(block.strength.kc.constants[section.len()..]
        .iter()
        .all(|v| *v == 0.0));
    let (card, length) = write_card(&block);
    for (slot, name) in section.iter().enumerate() {
        assert_eq!(
            card[28 + slot],
            material.parameters.get(name).unwrap(),
            "{name}"
        );
    }
    assert_eq!(read_card(&card[..length]).to_kc().unwrap(), material);
}

#[test]
fn kc_blocks_refuse_what_concrete_does_not_have() {
    // GOAL: metal-only options and broken tables on a K&C block are errors naming the field.
    // SETUP: the K&C defaults with, in turn, adiabatic heating, the lagged rate, JC failure,
    //        erosion and the pressure cut-off switched on, a bad rate code, one damage point,
    //        a negative fc and a non-finite surface constant.
    // REFERENCE: INVALID_PARAMETER and the field's name in the message.
    type Spoil = fn(&mut StossMaterialBlock);
    let cases: [(&str, Spoil); 9] = [
        ("heating_model", |b| b.heating_model = 2),
        ("rate_treatment", |b| b.rate_treatment = 2),
        ("failure.johnson_cook_enabled", |b| {
            b.failure.johnson_cook_enabled = 1
        }),
        ("failure.erosion_enabled", |b| b.failure.erosion_enabled = 1),
        ("failure.pressure_cutoff_enabled", |b| {
            b.failure.pressure_cutoff_enabled = 1
        }),
        ("strength.kc.rate", |b| b.strength.kc.rate = 9),
        ("strength.kc.damage_point_count", |b| {
            b.strength.kc.damage_point_count = 1
        }),
        ("compressive_strength", |b| {
            b.strength.kc.constants[0] = -1.0
        }),
        ("strength.kc", |b| b.strength.kc.yield_surface[1] = f64::NAN),
    ];
    for (field, spoil) in cases {
        let mut block = kc_concrete();
        spoil(&mut block);
        let (status, message) = validate(&block);
        assert_eq!(status, StossStatus::InvalidParameter, "{field}: {message}");
        assert!(message.contains(field), "{field}: {message}");
    }
}

#[test]
fn described_sections_match_the_generated_header() {
    // GOAL: the sections read through the kernel's descriptor have, in the generated C
    //       header, the descriptor's constants in its order (RHT: named fields; K&C: an
    //       array as long as the descriptor allows).
    // SETUP: include/stoss_kernel.h as committed (its drift from the Rust source is
    //        checked by .ci/ffi.sh).
    // REFERENCE: RhtParameters::PARAMETERS and KcParameters::PARAMETERS without the shear
    //            modulus.
    let header = include_str!("../include/stoss_kernel.h");
    let body = |name: &str| -> Vec<String> {
        let start = header
            .find(&format!("typedef struct {name} {{"))
            .unwrap_or_else(|| panic!("{name} in the header"));
        let end = start + header[start..].find(&format!("}} {name};")).unwrap();
        header[start..end]
            .lines()
            .skip(1)
            .map(str::trim)
            .filter(|line| !line.starts_with("//") && !line.is_empty())
            .map(str::to_owned)
            .collect()
    };
    // A named section's doubles, in the header's order, are its `FIELDS`, which the
    // compile-time checks of `described_section!` prove to be the struct's fields and exactly
    // the family's described constants.
    fn doubles(lines: &[String]) -> Vec<String> {
        lines
            .iter()
            .filter_map(|line| line.strip_prefix("double "))
            .map(|field| field.trim_end_matches(';').to_owned())
            .collect()
    }
    fn fields<S: DescribedSection>() -> Vec<String> {
        S::FIELDS.iter().map(|name| name.to_string()).collect()
    }
    assert_eq!(doubles(&body("StossRht")), fields::<StossRht>());
    assert_eq!(
        doubles(&body("StossJohnsonCook")),
        fields::<StossJohnsonCook>()
    );
    assert_eq!(
        doubles(&body("StossZerilliArmstrong")),
        fields::<StossZerilliArmstrong>()
    );
    assert_eq!(
        doubles(&body("StossModifiedJohnsonCook")),
        fields::<StossModifiedJohnsonCook>()
    );
    assert_eq!(
        doubles(&body("StossTwoRateJohnsonCook")),
        fields::<StossTwoRateJohnsonCook>()
    );
    assert_eq!(
        doubles(&body("StossPrestonTonksWallace")),
        fields::<StossPrestonTonksWallace>()
    );
    assert_eq!(
        doubles(&body("StossKhanHuangLiang")),
        fields::<StossKhanHuangLiang>()
    );
    assert_eq!(doubles(&body("StossVoceKocks")), fields::<StossVoceKocks>());
    assert_eq!(
        doubles(&body("StossMechanicalThresholdStress")),
        fields::<StossMechanicalThresholdStress>()
    );
    // RHT's public order happens to be its descriptor's.
    let described: Vec<&str> = stoss_kernel::rht::RhtParameters::PARAMETERS
        .iter()
        .map(|p| p.name)
        .filter(|name| *name != "shear_modulus")
        .collect();
    assert_eq!(<StossRht as DescribedSection>::FIELDS, described.as_slice());
    let kc = body("StossKc");
    assert!(kc.contains(&"double constants[STOSS_KC_MAX_CONSTANTS];".to_owned()));
    assert!(header.contains(&format!(
        "#define STOSS_KC_MAX_CONSTANTS {}\n",
        stoss_kernel_ffi::block::STOSS_KC_MAX_CONSTANTS
    )));
}
