//! A rigid planar wall of finite mass moving along its normal: the striker face of a drop
//! weight (LS-DYNA `*RIGIDWALL_PLANAR_MOVING` with `MASS` and `V0`).
//!
//! The contact is a kinematic constraint, as for the fixed walls: at each step the wall's
//! velocity `w` along its normal `n` and the normal velocities of the slave nodes that would
//! cross it are made consistent, with the momentum of the wall and those nodes conserved
//! (a perfectly plastic impact per node, as a fixed wall's):
//!
//! - a slave node at distance `g_i = (x_i - p) . n - s` from the wall (`s` its displacement)
//!   crosses it during the step when `a_i = v_i . n + g_i / dt < w`;
//! - the nodes that touch are the `k` with the smallest `a_i` for which
//!   `w' = (M w + sum_k m_i a_i) / (M + sum_k m_i)` stays above every `a_i` taken (the
//!   largest such set; `w'` is then below the next `a_i`);
//! - each node in contact gets `v_i . n = w' - g_i / dt` (it closes its gap exactly) and a
//!   Coulomb friction change of its tangential velocity of at most `mu` times its normal
//!   change, against a wall that does not move sideways (a guided drop weight).
//!
//! The wall carries its kinetic energy `M w^2 / 2` in the balance and gravity, when the model
//! has one, acts on it too. The energy the impacts absorb (normal stop and friction) is booked
//! as contact energy: the work of the nodes' velocity changes and the wall's
//! `M dw (w_old + w') / 2`, with the same mid-step mean velocities as every other kinematic
//! change.

use super::explicit::Vector;

/// The motion of a rigid wall of finite mass along its normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallMotion {
    /// Mass of the wall and whatever moves with it (kg; in an axisymmetric model the whole
    /// body's mass, not per radian).
    pub mass: f64,
    /// Initial velocity along the wall's normal (m/s; positive moves the wall into the
    /// allowed half-space, towards the body).
    pub velocity: f64,
}

/// The state of a wall at a record time.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WallState {
    /// Displacement along the normal since the start (m).
    pub displacement: f64,
    /// Velocity along the normal (m/s), at the half step.
    pub velocity: f64,
    /// Force of the contact on the wall along its normal over the last step (N; negative
    /// decelerates a wall moving along its normal), total over the model's symmetry measure.
    pub contact_force: f64,
}

/// One step's result of a moving wall.
pub(crate) struct WallStep {
    /// The wall's velocity before the contact (after gravity).
    pub(crate) free_velocity: f64,
    /// Its velocity after the contact.
    pub(crate) velocity: f64,
}

/// Resolve the contact of a moving wall (point `point` at displacement `displacement`,
/// normal `normal`, mass per measure `mass`, velocity `velocity` after the step's gravity) with
/// its slave nodes for a step `dt`: set the touching nodes' velocities and record their
/// changes in `velocity_change`. `order` is a scratch buffer.
#[allow(clippy::too_many_arguments)]
pub(crate) fn resolve(
    point: &Vector,
    normal: &Vector,
    displacement: f64,
    mass: f64,
    velocity: f64,
    friction: f64,
    slaves: &[usize],
    node_mass: &[f64],
    x: &[Vector],
    v: &mut [Vector],
    velocity_change: &mut [Vector],
    dt: f64,
    dimension: usize,
    order: &mut Vec<(f64, usize)>,
) -> WallStep {
    let dot = |a: &Vector, b: &Vector| (0..dimension).map(|d| a[d] * b[d]).sum::<f64>();
    order.clear();
    for &n in slaves {
        if node_mass[n] <= 0.0 {
            continue;
        }
        let offset: Vector = core::array::from_fn(|d| x[n][d] - point[d]);
        let gap = dot(&offset, normal) - displacement;
        let approach = dot(&v[n], normal) + gap / dt;
        if approach < velocity {
            order.push((approach, n));
        }
    }
    // Ascending approach, ties by node: the same set and sums for any input order.
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let (mut momentum, mut total) = (mass * velocity, mass);
    let mut taken = 0;
    for &(approach, n) in order.iter() {
        if approach >= momentum / total {
            break;
        }
        momentum += node_mass[n] * approach;
        total += node_mass[n];
        taken += 1;
    }
    let new_velocity = momentum / total;
    for &(approach, n) in &order[..taken] {
        let before = v[n];
        let vn = dot(&v[n], normal);
        let gap = (approach - vn) * dt;
        let vn_new = new_velocity - gap / dt;
        let dvn = vn_new - vn;
        let mut vt: Vector = core::array::from_fn(|d| v[n][d] - vn * normal[d]);
        let speed_t = dot(&vt, &vt).sqrt();
        if speed_t > 0.0 {
            let keep = (speed_t - (friction * dvn.abs()).min(speed_t)) / speed_t;
            vt = vt.map(|c| c * keep);
        }
        for d in 0..dimension {
            v[n][d] = vt[d] + vn_new * normal[d];
            velocity_change[n][d] += v[n][d] - before[d];
        }
    }
    WallStep {
        free_velocity: velocity,
        velocity: new_velocity,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_wall_and_the_nodes_it_strikes_keep_their_momentum() {
        // GOAL: the striker's contact conserves momentum and closes every gap it takes.
        // SETUP: wall at z = 0 moving down (normal -z) at 10 m/s, mass 3 kg; three unit-mass
        //        nodes 1 mm below at rest, one 5 mm below; dt 1e-4 s.
        // REFERENCE: the three near nodes have `a_i = v.n + g/dt` = 0 + 1e-3/1e-4 = 10 m/s,
        //            not below w = 10: none is struck yet. With
        //            dt 2e-4 their `a_i` = 5 m/s: all three are taken, w' = (30 + 15) / 6
        //            = 7.5 m/s, each node's normal velocity 7.5 - 5 = 2.5 m/s (new gap 0);
        //            the far node (`a` = 25 m/s) is untouched; momentum 30 kg m/s before and
        //            after.
        let normal = [0.0, 0.0, -1.0];
        let x = vec![
            [0.0, 0.0, -1e-3],
            [1.0, 0.0, -1e-3],
            [2.0, 0.0, -1e-3],
            [3.0, 0.0, -5e-3],
        ];
        let masses = [1.0; 4];
        let mut order = Vec::new();
        let mut v = vec![[0.0; 3]; 4];
        let mut change = vec![[0.0; 3]; 4];
        let slaves = [0, 1, 2, 3];
        let step = resolve(
            &[0.0; 3],
            &normal,
            0.0,
            3.0,
            10.0,
            0.0,
            &slaves,
            &masses,
            &x,
            &mut v,
            &mut change,
            1e-4,
            3,
            &mut order,
        );
        assert_eq!(step.velocity, 10.0);
        assert!(v.iter().all(|v| *v == [0.0; 3]));
        let step = resolve(
            &[0.0; 3],
            &normal,
            0.0,
            3.0,
            10.0,
            0.0,
            &slaves,
            &masses,
            &x,
            &mut v,
            &mut change,
            2e-4,
            3,
            &mut order,
        );
        assert!((step.velocity - 7.5).abs() < 1e-12);
        for node in &v[..3] {
            assert!((node[2] + 2.5).abs() < 1e-12, "{node:?}");
        }
        assert_eq!(v[3], [0.0; 3]);
        let momentum = 3.0 * step.velocity + v.iter().map(|v| -v[2]).sum::<f64>();
        assert!((momentum - 30.0).abs() < 1e-12);
    }

    #[test]
    fn a_heavy_wall_takes_only_the_nodes_it_still_outruns() {
        // GOAL: the contact set is the largest consistent one: a node that the slowed wall no
        //       longer reaches is not pulled along.
        // SETUP: wall of mass 1 kg at 10 m/s (normal -z); node A (1 kg) at rest on the wall
        //        (gap 0, a = 0); node B (1 kg) at rest 0.9 mm away (a = 9 m/s at dt 1e-4).
        // REFERENCE: taking A gives w' = 5 m/s < 9: B is not struck; A moves at 5 m/s.
        let normal = [0.0, 0.0, -1.0];
        let x = vec![[0.0, 0.0, 0.0], [1.0, 0.0, -0.9e-3]];
        let mut v = vec![[0.0; 3]; 2];
        let mut change = vec![[0.0; 3]; 2];
        let mut order = Vec::new();
        let step = resolve(
            &[0.0; 3],
            &normal,
            0.0,
            1.0,
            10.0,
            0.0,
            &[0, 1],
            &[1.0, 1.0],
            &x,
            &mut v,
            &mut change,
            1e-4,
            3,
            &mut order,
        );
        assert!((step.velocity - 5.0).abs() < 1e-12);
        assert!((v[0][2] + 5.0).abs() < 1e-12);
        assert_eq!(v[1], [0.0; 3]);
    }
}
