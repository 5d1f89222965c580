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

/// A rigid, fixed, planar wall. Nodes of `nodes` (or all nodes if empty) may not cross it.
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
}

/// Mass-proportional nodal damping, used to bring a structure to rest and read its final
/// shape (LS-DYNA *DAMPING_GLOBAL): `v <- v (1 - coefficient dt)` from `start_time` on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NodalDamping {
    /// Time at which damping starts (s).
    pub start_time: f64,
    /// Damping coefficient (1/s).
    pub coefficient: f64,
}
