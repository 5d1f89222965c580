//! The batch (structure-of-arrays) interface: one call updates `n` integration points, like
//! VUMAT's `nblock`, LS-DYNA's vectorised `umat4Xv` or an OpenRadioss element group.
//!
//! Every per-point quantity is its own contiguous array of `n` values (`stress[0][i]` is
//! `sigma_xx` of point `i`). Points are independent: a point whose update fails gets its
//! status and keeps its state untouched; the others proceed.

use stoss_kernel::eos::Eos;
use stoss_kernel::kc::KcMaterial;
use stoss_kernel::math::exp;
use stoss_kernel::rht::RhtMaterial;
use stoss_kernel::tensor::{self, Matrix6, Sym};
use stoss_kernel::PartMaterial;
use stoss_kernel::{
    Material, MaterialState, PointModel, StateFlags, StepInput, StepOutput, UpdateError,
    YieldCheck, LANES,
};

use crate::boundary::{ArrayIn, ArrayOut};
use crate::status::{FfiError, StossStatus};

/// `failed` output bit: damage reached 1; the point carries no shear and no tension.
pub const STOSS_FAILED_DAMAGE: i32 = 1;
/// `failed` output bit: the host should erode (delete) the element.
pub const STOSS_FAILED_ERODE: i32 = 2;

/// Inputs of a batch: strain increments (Voigt `xx yy zz xy yz zx`, **tensor** shear), and
/// optionally the relative volume `V/V0` at the end of the step.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct StossBatchInput {
    /// Six arrays of `n` strain increments: `strain_increment[k][i]`, component `k` of point `i`.
    pub strain_increment: [*const f64; 6],
    /// `n` relative volumes `V/V0` at the end of the step, or NULL: then each point integrates
    /// its own, `V1 = V0 exp(tr deps)` (consistent with logarithmic strain increments; this is
    /// what stoss's single-element drivers do).
    pub relative_volume: *const f64,
}

/// The in/out state of a batch: one array of `n` values per history quantity. All required.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct StossBatchState {
    /// Cauchy stress (Pa), six arrays in Voigt order, tension positive.
    pub stress: [*mut f64; 6],
    /// Equivalent plastic strain (-).
    pub plastic_strain: *mut f64,
    /// Equivalent plastic strain rate of the last step (1/s).
    pub plastic_strain_rate: *mut f64,
    /// Temperature (K).
    pub temperature: *mut f64,
    /// Damage in [0, 1].
    pub damage: *mut f64,
    /// Relative volume `V/V0` (-), > 0.
    pub relative_volume: *mut f64,
    /// Internal energy per unit **reference** volume (J/m^3).
    pub internal_energy: *mut f64,
    /// EoS history variable (P-alpha distension, tabulated-compaction maximum strain; else 0).
    pub eos_history: *mut f64,
    /// State flags (`STOSS_STATE_PLASTIC`, `_FAILED`, `_ERODE`, `_PRESSURE_CUTOFF`).
    pub flags: *mut u32,
}

/// Per-point outputs of a batch; every array may be NULL (not wanted).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct StossBatchOutput {
    /// `n` longitudinal wave speeds (m/s) for the host's CFL time step.
    pub wave_speed: *mut f64,
    /// `n` failure codes: `STOSS_FAILED_DAMAGE | STOSS_FAILED_ERODE` bits (0: intact).
    pub failed: *mut i32,
    /// `n` statuses (`StossStatus` values), `STOSS_STATUS_OK` for points that succeeded.
    pub status: *mut i32,
    /// `36 n` values: the consistent tangent of point `i` at `tangent[36 i + 6 r + c]`,
    /// `d sigma_r / d deps_c` (Voigt, tensor-shear columns).
    pub tangent: *mut f64,
}

/// State flag: the point yielded in the last step.
pub const STOSS_STATE_PLASTIC: u32 = 1;
/// State flag: damage reached 1.
pub const STOSS_STATE_FAILED: u32 = 2;
/// State flag: the host should erode the element.
pub const STOSS_STATE_ERODE: u32 = 4;
/// State flag: the pressure was held at the cut-off in the last step.
pub const STOSS_STATE_PRESSURE_CUTOFF: u32 = 8;

// The ABI's flag values are the kernel's (literals above so that cbindgen can emit them).
const _: () = assert!(
    STOSS_STATE_PLASTIC == StateFlags::PLASTIC
        && STOSS_STATE_FAILED == StateFlags::FAILED
        && STOSS_STATE_ERODE == StateFlags::ERODE
        && STOSS_STATE_PRESSURE_CUTOFF == StateFlags::PRESSURE_CUTOFF
);

/// The failure code (`STOSS_FAILED_*` bits) of a state.
pub fn failure_code(state: &MaterialState) -> i32 {
    let mut code = 0;
    if state.flags.contains(StateFlags::FAILED) {
        code |= STOSS_FAILED_DAMAGE;
    }
    if state.flags.contains(StateFlags::ERODE) {
        code |= STOSS_FAILED_ERODE;
    }
    code
}

/// A kernel point model the ABI runs (a J2 metal or RHT concrete): the kernel's
/// [`PointModel`], and the EoS the host's bulk modulus and wave speed come from.
pub trait AbiModel: PointModel {
    /// The model's equation of state.
    fn eos(&self) -> &Eos;
}

impl AbiModel for Material {
    fn eos(&self) -> &Eos {
        &self.eos
    }
}

impl AbiModel for RhtMaterial {
    fn eos(&self) -> &Eos {
        &self.eos
    }
}

impl AbiModel for KcMaterial {
    fn eos(&self) -> &Eos {
        &self.eos
    }
}

impl AbiModel for PartMaterial {
    fn eos(&self) -> &Eos {
        match self {
            PartMaterial::J2(material) => material.eos(),
            PartMaterial::Rht(material) => material.eos(),
            PartMaterial::Kc(material) => material.eos(),
        }
    }
}

/// One point, one step: the kernel update with the relative volume either given or
/// integrated as `V1 = V0 exp(tr deps)` (bit-identical to the kernel's drivers).
#[inline]
pub fn step_point<M: PointModel>(
    material: &M,
    state: &mut MaterialState,
    strain_increment: &Sym,
    dt: f64,
    relative_volume: Option<f64>,
    tangent: Option<&mut Matrix6>,
) -> Result<StepOutput, UpdateError> {
    let input = step_input(state, strain_increment, dt, relative_volume);
    match tangent {
        Some(tangent) => material.update_with_tangent(state, &input, tangent),
        None => material.update(state, &input),
    }
}

/// One point's step input, the relative volume either given or integrated as
/// `V1 = V0 exp(tr deps)` (bit-identical to the kernel's drivers).
#[inline]
pub(crate) fn step_input(
    state: &MaterialState,
    strain_increment: &Sym,
    dt: f64,
    relative_volume: Option<f64>,
) -> StepInput {
    let relative_volume = match relative_volume {
        Some(volume) => volume,
        None => state.relative_volume * exp(tensor::trace(strain_increment)),
    };
    StepInput {
        strain_increment: *strain_increment,
        dt,
        relative_volume,
    }
}

/// Checked views of a batch's input arrays.
pub(crate) struct InputViews<'a> {
    pub strain_increment: [ArrayIn<'a, f64>; 6],
    pub relative_volume: Option<ArrayIn<'a, f64>>,
}

impl InputViews<'_> {
    /// # Safety
    /// Every pointer in `input` is NULL or valid for reads of `n` elements.
    pub(crate) unsafe fn new(input: &StossBatchInput, n: usize) -> Result<Self, FfiError> {
        let mut strain_increment = [ArrayIn::empty(); 6];
        for (k, pointer) in input.strain_increment.iter().enumerate() {
            // SAFETY: forwarded caller contract.
            strain_increment[k] = unsafe { ArrayIn::new(*pointer, n, INPUT_NAMES[k]) }?;
        }
        Ok(Self {
            strain_increment,
            // SAFETY: forwarded caller contract.
            relative_volume: unsafe {
                ArrayIn::optional(input.relative_volume, n, "input.relative_volume")
            }?,
        })
    }
}

/// Checked views of a batch's optional output arrays.
pub(crate) struct OutputViews<'a> {
    pub wave_speed: Option<ArrayOut<'a, f64>>,
    pub failed: Option<ArrayOut<'a, i32>>,
    pub status: Option<ArrayOut<'a, i32>>,
    pub tangent: Option<ArrayOut<'a, f64>>,
}

impl OutputViews<'_> {
    /// No outputs.
    pub(crate) fn none() -> Self {
        Self {
            wave_speed: None,
            failed: None,
            status: None,
            tangent: None,
        }
    }

    /// # Safety
    /// Every pointer in `output` is NULL or valid for writes of `n` elements (`36 n` for the
    /// tangent).
    pub(crate) unsafe fn new(output: &StossBatchOutput, n: usize) -> Result<Self, FfiError> {
        let tangent_len = n.checked_mul(36).ok_or_else(|| {
            FfiError::new(
                StossStatus::InvalidArgument,
                format!("n: {n} points overflow 36 n"),
            )
        })?;
        // SAFETY: forwarded caller contract, for every array below.
        unsafe {
            Ok(Self {
                wave_speed: ArrayOut::optional(output.wave_speed, n, "output.wave_speed")?,
                failed: ArrayOut::optional(output.failed, n, "output.failed")?,
                status: ArrayOut::optional(output.status, n, "output.status")?,
                tangent: ArrayOut::optional(output.tangent, tangent_len, "output.tangent")?,
            })
        }
    }
}

/// Checked views of the state arrays only.
pub(crate) struct StateViews<'a> {
    pub stress: [ArrayOut<'a, f64>; 6],
    pub plastic_strain: ArrayOut<'a, f64>,
    pub plastic_strain_rate: ArrayOut<'a, f64>,
    pub temperature: ArrayOut<'a, f64>,
    pub damage: ArrayOut<'a, f64>,
    pub relative_volume: ArrayOut<'a, f64>,
    pub internal_energy: ArrayOut<'a, f64>,
    pub eos_history: ArrayOut<'a, f64>,
    pub flags: ArrayOut<'a, u32>,
}

/// Argument names for messages (static: no allocation on the success path).
const INPUT_NAMES: [&str; 6] = [
    "input.strain_increment[0] (xx)",
    "input.strain_increment[1] (yy)",
    "input.strain_increment[2] (zz)",
    "input.strain_increment[3] (xy)",
    "input.strain_increment[4] (yz)",
    "input.strain_increment[5] (zx)",
];
const STRESS_NAMES: [&str; 6] = [
    "state.stress[0] (xx)",
    "state.stress[1] (yy)",
    "state.stress[2] (zz)",
    "state.stress[3] (xy)",
    "state.stress[4] (yz)",
    "state.stress[5] (zx)",
];

impl<'a> StateViews<'a> {
    /// # Safety
    /// Every pointer in `state` is NULL or valid for reads and writes of `n` elements.
    pub(crate) unsafe fn new(state: &StossBatchState, n: usize) -> Result<Self, FfiError> {
        let mut stress = [(); 6].map(|()| ArrayOut::empty());
        for (k, pointer) in state.stress.iter().enumerate() {
            // SAFETY: forwarded caller contract.
            stress[k] = unsafe { ArrayOut::new(*pointer, n, STRESS_NAMES[k]) }?;
        }
        // SAFETY: forwarded caller contract, for every array below.
        unsafe {
            Ok(Self {
                stress,
                plastic_strain: ArrayOut::new(state.plastic_strain, n, "state.plastic_strain")?,
                plastic_strain_rate: ArrayOut::new(
                    state.plastic_strain_rate,
                    n,
                    "state.plastic_strain_rate",
                )?,
                temperature: ArrayOut::new(state.temperature, n, "state.temperature")?,
                damage: ArrayOut::new(state.damage, n, "state.damage")?,
                relative_volume: ArrayOut::new(state.relative_volume, n, "state.relative_volume")?,
                internal_energy: ArrayOut::new(state.internal_energy, n, "state.internal_energy")?,
                eos_history: ArrayOut::new(state.eos_history, n, "state.eos_history")?,
                flags: ArrayOut::new(state.flags, n, "state.flags")?,
            })
        }
    }

    pub(crate) fn write(&mut self, i: usize, state: &MaterialState) {
        for (k, array) in self.stress.iter_mut().enumerate() {
            array.set(i, state.stress[k]);
        }
        self.plastic_strain.set(i, state.plastic_strain);
        self.plastic_strain_rate.set(i, state.plastic_strain_rate);
        self.temperature.set(i, state.temperature);
        self.damage.set(i, state.damage);
        self.relative_volume.set(i, state.relative_volume);
        self.internal_energy.set(i, state.internal_energy);
        self.eos_history.set(i, state.eos_history);
        self.flags.set(i, state.flags.0);
    }

    /// Whether every array holds at least `n` elements.
    fn covers(&self, n: usize) -> bool {
        self.stress.iter().all(|a| a.covers(n))
            && self.plastic_strain.covers(n)
            && self.plastic_strain_rate.covers(n)
            && self.temperature.covers(n)
            && self.damage.covers(n)
            && self.relative_volume.covers(n)
            && self.internal_energy.covers(n)
            && self.eos_history.covers(n)
            && self.flags.covers(n)
    }

    /// [`StateViews::read`] without the bounds checks.
    ///
    /// # Safety
    /// `i < n` for an `n` that [`StateViews::covers`].
    #[inline]
    unsafe fn read_unchecked(&self, i: usize) -> MaterialState {
        // SAFETY: `i < n <= len` of every array (caller).
        unsafe {
            MaterialState {
                stress: core::array::from_fn(|k| self.stress[k].get_unchecked(i)),
                plastic_strain: self.plastic_strain.get_unchecked(i),
                plastic_strain_rate: self.plastic_strain_rate.get_unchecked(i),
                temperature: self.temperature.get_unchecked(i),
                damage: self.damage.get_unchecked(i),
                relative_volume: self.relative_volume.get_unchecked(i),
                internal_energy: self.internal_energy.get_unchecked(i),
                eos_history: self.eos_history.get_unchecked(i),
                flags: StateFlags(self.flags.get_unchecked(i)),
                yield_check: YieldCheck::NONE,
            }
        }
    }

    /// [`StateViews::write`] without the bounds checks.
    ///
    /// # Safety
    /// `i < n` for an `n` that [`StateViews::covers`].
    #[inline]
    unsafe fn write_unchecked(&mut self, i: usize, state: &MaterialState) {
        // SAFETY: `i < n <= len` of every array (caller).
        unsafe {
            for (k, array) in self.stress.iter_mut().enumerate() {
                array.set_unchecked(i, state.stress[k]);
            }
            self.plastic_strain.set_unchecked(i, state.plastic_strain);
            self.plastic_strain_rate
                .set_unchecked(i, state.plastic_strain_rate);
            self.temperature.set_unchecked(i, state.temperature);
            self.damage.set_unchecked(i, state.damage);
            self.relative_volume.set_unchecked(i, state.relative_volume);
            self.internal_energy.set_unchecked(i, state.internal_energy);
            self.eos_history.set_unchecked(i, state.eos_history);
            self.flags.set_unchecked(i, state.flags.0);
        }
    }
}

/// Update `n` points; returns the first failure (index and error) after processing all.
pub(crate) fn run_batch<M: PointModel>(
    material: &M,
    n: usize,
    dt: f64,
    input: &InputViews<'_>,
    state: &mut StateViews<'_>,
    output: &mut OutputViews<'_>,
) -> Option<(usize, UpdateError)> {
    let mut first_failure = None;
    let want_tangent = output.tangent.is_some();
    // Every array is checked once to hold `n` points (36 n tangent entries), so the loop
    // reads and writes without a bounds check per access. The views are built with `n` by
    // the exports; a shorter one is a defect here, a panic caught at the boundary.
    let covered = input.strain_increment.iter().all(|a| a.covers(n))
        && input.relative_volume.as_ref().is_none_or(|a| a.covers(n))
        && state.covers(n)
        && output.wave_speed.as_ref().is_none_or(|a| a.covers(n))
        && output.failed.as_ref().is_none_or(|a| a.covers(n))
        && output.status.as_ref().is_none_or(|a| a.covers(n))
        && output
            .tangent
            .as_ref()
            .is_none_or(|a| n.checked_mul(36).is_some_and(|len| a.covers(len)));
    assert!(covered, "a batch view holds fewer than {n} points");
    // Without a tangent the points go through the model's group update, LANES at a time
    // (bit for bit the one-point update); the rest, and every point when the host asks for
    // the tangent, one at a time.
    let grouped = if want_tangent { 0 } else { n - n % LANES };
    // One group's points, steps and results, every entry overwritten for each group.
    let mut points = [MaterialState::initial(0.0); LANES];
    let mut inputs = [zero_step(dt); LANES];
    let mut results = [Err(UpdateError::NonFiniteInput); LANES];
    for first in (0..grouped).step_by(LANES) {
        for (lane, (point, step)) in points.iter_mut().zip(inputs.iter_mut()).enumerate() {
            let i = first + lane;
            // SAFETY: `i < grouped <= n`, covered (above).
            *point = unsafe { state.read_unchecked(i) };
            let increment = read_increment(input, i);
            let volume = read_volume(input, i);
            *step = step_input(point, &increment, dt, volume);
        }
        material.update_lanes(&mut points, &inputs, &mut results);
        for (lane, (point, result)) in points.iter().zip(&results).enumerate() {
            store(
                first + lane,
                result,
                point,
                None,
                state,
                output,
                &mut first_failure,
            );
        }
    }
    for i in grouped..n {
        let increment = read_increment(input, i);
        let volume = read_volume(input, i);
        // SAFETY: `i < n`, covered (above).
        let mut point = unsafe { state.read_unchecked(i) };
        // The tangent is formed (and its 36 entries zeroed) only when the host asks for it.
        let mut matrix: Option<Matrix6> = want_tangent.then_some([[0.0; 6]; 6]);
        let result = step_point(
            material,
            &mut point,
            &increment,
            dt,
            volume,
            matrix.as_mut(),
        );
        store(
            i,
            &result,
            &point,
            matrix.as_ref(),
            state,
            output,
            &mut first_failure,
        );
    }
    first_failure
}

/// A step of length `dt` with no strain: the placeholder of a group's step arrays.
#[inline(always)]
pub(crate) fn zero_step(dt: f64) -> StepInput {
    StepInput {
        strain_increment: [0.0; 6],
        dt,
        relative_volume: 1.0,
    }
}

/// Point `i`'s strain increment. Requires `i` below the count the views were checked to cover
/// (`run_batch`).
#[inline(always)]
fn read_increment(input: &InputViews<'_>, i: usize) -> Sym {
    core::array::from_fn(|k| {
        // SAFETY: `i < n`, and `run_batch` checked every input array to cover `n` points.
        unsafe { input.strain_increment[k].get_unchecked(i) }
    })
}

/// Point `i`'s relative volume, if the host gives it. Requires `i` as [`read_increment`].
#[inline(always)]
fn read_volume(input: &InputViews<'_>, i: usize) -> Option<f64> {
    input.relative_volume.as_ref().map(|v| {
        // SAFETY: `i < n`, and `run_batch` checked the volume array to cover `n` points.
        unsafe { v.get_unchecked(i) }
    })
}

/// Writes point `i`'s step: its new state, wave speed, failure code and tangent (if given) on
/// success, its status always; the first failure is kept. Requires `i` as [`read_increment`].
#[inline(always)]
fn store(
    i: usize,
    result: &Result<StepOutput, UpdateError>,
    point: &MaterialState,
    matrix: Option<&Matrix6>,
    state: &mut StateViews<'_>,
    output: &mut OutputViews<'_>,
    first_failure: &mut Option<(usize, UpdateError)>,
) {
    let status = match result {
        Ok(step) => {
            // SAFETY: `i < n`, and `run_batch` checked every view to cover `n` points.
            unsafe { state.write_unchecked(i, point) };
            if let Some(array) = &mut output.wave_speed {
                // SAFETY: as above.
                unsafe { array.set_unchecked(i, step.wave_speed) };
            }
            if let Some(array) = &mut output.failed {
                // SAFETY: as above.
                unsafe { array.set_unchecked(i, failure_code(point)) };
            }
            if let (Some(tangent), Some(matrix)) = (&mut output.tangent, matrix) {
                for (r, row) in matrix.iter().enumerate() {
                    for (c, value) in row.iter().enumerate() {
                        // SAFETY: `36 i + 6 r + c < 36 n`, covered (`run_batch`).
                        unsafe { tangent.set_unchecked(36 * i + 6 * r + c, *value) };
                    }
                }
            }
            StossStatus::Ok
        }
        Err(error) => {
            if first_failure.is_none() {
                *first_failure = Some((i, *error));
            }
            StossStatus::from(*error)
        }
    };
    if let Some(array) = &mut output.status {
        // SAFETY: as above.
        unsafe { array.set_unchecked(i, status as i32) };
    }
}
