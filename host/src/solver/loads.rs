//! Boundary conditions, initial conditions and rigid walls.

/// A piecewise-linear function of time, constant outside its table.
#[derive(Clone, Debug, PartialEq)]
pub struct Amplitude {
    /// `(time, value)` pairs, times strictly increasing.
    pub points: Vec<(f64, f64)>,
}

impl Amplitude {
    /// A constant value.
    pub fn constant(value: f64) -> Self {
        Self {
            points: vec![(0.0, value)],
        }
    }

    /// A ramp from 0 at `t = 0` to `value` at `rise_time`, then constant (the smoothed
    /// loading pulse of seed 001 sec. 3.4.1).
    pub fn ramp(value: f64, rise_time: f64) -> Self {
        if rise_time <= 0.0 {
            return Self::constant(value);
        }
        Self {
            points: vec![(0.0, 0.0), (rise_time, value)],
        }
    }

    /// Value at time `t`.
    pub fn at(&self, t: f64) -> f64 {
        let points = &self.points;
        match points.iter().position(|&(time, _)| time > t) {
            None => points.last().map_or(0.0, |p| p.1),
            Some(0) => points[0].1,
            Some(k) => {
                let (t0, v0) = points[k - 1];
                let (t1, v1) = points[k];
                v0 + (v1 - v0) * (t - t0) / (t1 - t0)
            }
        }
    }
}

/// A prescribed velocity on one degree of freedom of a set of nodes (zero = fixed).
#[derive(Clone, Debug, PartialEq)]
pub struct VelocityConstraint {
    /// Node indices.
    pub nodes: Vec<usize>,
    /// Degree of freedom (0 = r or x, 1 = z or y, 2 = z in 3D).
    pub dof: usize,
    /// Velocity history (m/s).
    pub velocity: Amplitude,
}

/// A rigid planar wall, fixed (LS-DYNA `*RIGIDWALL_PLANAR`) or moving along its normal with a
/// finite mass (`*RIGIDWALL_PLANAR_MOVING`, [`super::moving_wall`]). Nodes of `nodes` (or all
/// nodes if empty) may not cross it.
#[derive(Clone, Debug, PartialEq)]
pub struct RigidWall {
    /// A point on the wall.
    pub point: Vec<f64>,
    /// Unit normal pointing into the allowed half-space.
    pub normal: Vec<f64>,
    /// Coulomb friction coefficient (0 = frictionless; `f64::INFINITY` = no slip).
    pub friction: f64,
    /// Slave nodes; empty means every node.
    pub nodes: Vec<usize>,
    /// `None`: the wall is fixed; else its mass and initial velocity along its normal.
    pub motion: Option<super::WallMotion>,
}

/// Mass-proportional nodal damping, used to bring a structure to rest and read its final
/// shape (LS-DYNA *DAMPING_GLOBAL): `v <- v (1 - coefficient dt)` from the start that
/// [`DampingStart`] gives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NodalDamping {
    /// The start time the rule refers to (s).
    pub start_time: f64,
    /// Damping coefficient (1/s).
    pub coefficient: f64,
    /// How the end of the plastic event moves the start.
    pub start: DampingStart,
}

/// When nodal damping starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DampingStart {
    /// At `start_time`.
    Fixed,
    /// At the first output at which the plastic event is over, or at `start_time` if that
    /// comes first (the Taylor test: a late fixed start only costs cycles).
    SettledOrAt(PlasticSettle),
    /// At the first output at or after `start_time` at which the plastic event is over, and
    /// at `latest` whatever the plastic strain does (the blast plate: damping that acts
    /// while the structure still yields changes the permanent deformation it reads).
    SettledAfter {
        /// When the plastic event is over.
        settle: PlasticSettle,
        /// Start at this time even if it is not (s).
        latest: f64,
    },
}

impl DampingStart {
    /// The plastic-event criterion, if the start waits for or follows it.
    pub fn settle(&self) -> Option<PlasticSettle> {
        match *self {
            DampingStart::Fixed => None,
            DampingStart::SettledOrAt(settle) | DampingStart::SettledAfter { settle, .. } => {
                Some(settle)
            }
        }
    }
}

/// The plastic event is over at the first output at which the equivalent plastic strain summed
/// over the (uneroded) elements is positive and has grown by at most `fraction` of itself over
/// the last `window`: damping from then on removes elastic ringing only.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlasticSettle {
    /// Window (s).
    pub window: f64,
    /// Largest relative growth over the window.
    pub fraction: f64,
}

/// A pressure history over a surface, as a function of the initial radius and of time:
/// piecewise constant in time over records of length `interval` (record `k` covers
/// `[k interval, (k + 1) interval)`), linear in radius between `radii`, constant beyond the
/// last radius, zero before `t = 0` and after the last record. Stored as interval means, its
/// time integral is exact.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PressureHistory {
    /// Radii of the samples (m), increasing.
    pub radii: Vec<f64>,
    /// Length of each record (s).
    pub interval: f64,
    /// `values[k][i]`: mean pressure over record `k` at `radii[i]` (Pa).
    pub values: Vec<Vec<f64>>,
}

impl PressureHistory {
    /// Pressure at radius `r` and time `t`.
    pub fn at(&self, radius: f64, time: f64) -> f64 {
        if time.is_nan() || time < 0.0 || self.radii.is_empty() {
            return 0.0;
        }
        let k = (time / self.interval) as usize;
        match self.values.get(k) {
            Some(row) => interpolate_radius(&self.radii, row, radius),
            None => 0.0,
        }
    }

    /// The record in force at time `t` (`None` before 0 and after the last record).
    pub fn record(&self, time: f64) -> Option<&[f64]> {
        if time.is_nan() || time < 0.0 {
            return None;
        }
        self.values
            .get((time / self.interval) as usize)
            .map(Vec::as_slice)
    }

    /// The records overlapping `[start, end)` and their shares of it: the mean pressure over
    /// the interval is `sum share_k record_k`, so a central-difference step that applies it
    /// over `[t - dt_previous/2, t + dt/2)` delivers exactly the recorded impulse.
    pub fn overlaps(&self, start: f64, end: f64, shares: &mut Vec<(usize, f64)>) {
        shares.clear();
        let span = end - start;
        let (lo_time, hi_time) = (start.max(0.0), end.min(self.duration()));
        if !(span > 0.0 && hi_time > lo_time) {
            return;
        }
        let first = (lo_time / self.interval) as usize;
        let last = ((hi_time / self.interval) as usize).min(self.values.len() - 1);
        for k in first..=last {
            let lo = (k as f64 * self.interval).max(lo_time);
            let hi = ((k + 1) as f64 * self.interval).min(hi_time);
            if hi > lo {
                shares.push((k, (hi - lo) / span));
            }
        }
    }

    /// Interpolation weights of radius `r`: `value = (1 - w) row[lo] + w row[hi]`.
    pub fn radial_weights(&self, radius: f64) -> (usize, usize, f64) {
        let last = self.radii.len().saturating_sub(1);
        match self.radii.iter().position(|&r| r > radius) {
            None => (last, last, 0.0),
            Some(0) => (0, 0, 0.0),
            Some(k) => (
                k - 1,
                k,
                (radius - self.radii[k - 1]) / (self.radii[k] - self.radii[k - 1]),
            ),
        }
    }

    /// Time integral of the pressure at radius `r` (Pa s).
    pub fn impulse(&self, radius: f64) -> f64 {
        self.values
            .iter()
            .map(|row| interpolate_radius(&self.radii, row, radius))
            .sum::<f64>()
            * self.interval
    }

    /// End of the last record (s).
    pub fn duration(&self) -> f64 {
        self.values.len() as f64 * self.interval
    }

    /// The largest recorded pressure and its radius.
    pub fn peak(&self) -> (f64, f64) {
        let mut best = (0.0, 0.0);
        for row in &self.values {
            for (value, radius) in row.iter().zip(&self.radii) {
                if *value > best.0 {
                    best = (*value, *radius);
                }
            }
        }
        best
    }
}

fn interpolate_radius(radii: &[f64], values: &[f64], radius: f64) -> f64 {
    match radii.iter().position(|&r| r > radius) {
        None => values.last().copied().unwrap_or(0.0),
        Some(0) => values[0],
        Some(k) => {
            let t = (radius - radii[k - 1]) / (radii[k] - radii[k - 1]);
            values[k - 1] + t * (values[k] - values[k - 1])
        }
    }
}

/// A pressure history shared between the solver and whoever extends it.
pub type SharedPressure = std::sync::Arc<std::sync::RwLock<PressureHistory>>;

/// Share `history`.
pub fn shared(history: PressureHistory) -> SharedPressure {
    std::sync::Arc::new(std::sync::RwLock::new(history))
}

/// A pressure applied to boundary segments of a 2D axisymmetric model.
///
/// Segment `[a, b]` is pushed along its left normal `(-(z_b - z_a), r_b - r_a)/L` (order the
/// nodes so that it points into the body). The pressure is looked up at the segment's
/// initial mid-radius (the load stays with the material it was computed for) and times
/// `scale`; the consistent nodal forces per radian are `p n L (2 r_a + r_b)/6` and
/// `p n L (r_a + 2 r_b)/6`, with the current geometry (a follower load).
#[derive(Clone, Debug)]
pub struct PressureLoad {
    /// Boundary segments.
    pub segments: Vec<[usize; 2]>,
    /// The pressure history, shared so that a coupled calculation can extend it while the
    /// model runs (the solver reads it at every step).
    pub history: SharedPressure,
    /// Factor on the history.
    pub scale: f64,
}
