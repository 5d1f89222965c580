//! Contact between two faces meshed on the same planes: each node of the lower face meets the
//! node of the upper face above it (LS-DYNA's node-to-node contact of a small-sliding
//! interface), 2D or 3D. The drop weight's striker head on its pad.
//!
//! Each pair `(a, b)` has the gap `g = (x_b - x_a) . n` along the faces' common normal `n`
//! (pointing from `a`'s body into `b`'s). At each step, a pair that would close within the
//! step (`g + (v_b - v_a) . n dt < 0`) is closed exactly, with the pair's momentum conserved
//! (a perfectly plastic impact of the two nodes, as the rigid walls'):
//! `v_a . n' = (m_a v_a . n + m_b v_b . n + m_b g / dt) / (m_a + m_b)`,
//! `v_b . n' = v_a . n' - g / dt`. A separating pair exerts nothing (no adhesion). Coulomb
//! friction moves the two tangential velocities towards their common, momentum-conserving
//! value by at most `mu` times the normal impulse. The pairs share no node, so their order
//! does not matter; the velocity changes are booked as contact energy by the time loop, as
//! the walls' are.
//!
//! Valid while the faces slide little against each other (a fraction of an element): pairs are
//! fixed at the start.

use crate::solver::explicit::Vector;
use crate::solver::SolverError;

/// Node-to-node contact between two faces meshed on the same planes.
#[derive(Clone, Debug, PartialEq)]
pub struct NodeToNodeContact {
    /// `[lower, upper]` node pairs: the upper node lies at or beyond the lower along `normal`.
    pub pairs: Vec<[usize; 2]>,
    /// Unit normal from the lower face's body into the upper's.
    pub normal: Vec<f64>,
    /// Coulomb friction coefficient.
    pub friction: f64,
}

impl NodeToNodeContact {
    /// Check the pairs against `node_count` nodes: distinct nodes in every pair and across
    /// pairs, a unit normal, a friction >= 0.
    pub(crate) fn check(&self, node_count: usize) -> Result<(), SolverError> {
        let mut seen: Vec<usize> = self.pairs.iter().flatten().copied().collect();
        seen.sort_unstable();
        let distinct = seen.windows(2).all(|w| w[0] != w[1]);
        let length = self.normal.iter().map(|c| c * c).sum::<f64>().sqrt();
        if !distinct
            || seen.last().is_some_and(|&n| n >= node_count)
            || (length - 1.0).abs() > 1e-9
            || !(self.friction >= 0.0 && self.friction.is_finite())
        {
            return Err(SolverError::Model(format!(
                "node-to-node contact: its pairs must name distinct nodes of the mesh ({node_count} \
                 nodes), its normal be a unit vector and its friction >= 0 (normal {:?}, \
                 friction {})",
                self.normal, self.friction
            )));
        }
        Ok(())
    }

    /// Close the pairs that would cross within `dt`; record the velocity changes in
    /// `velocity_change`.
    pub(crate) fn resolve(
        &self,
        mass: &[f64],
        x: &[Vector],
        v: &mut [Vector],
        velocity_change: &mut [Vector],
        dt: f64,
        dimension: usize,
    ) {
        let normal: Vector = core::array::from_fn(|d| self.normal.get(d).copied().unwrap_or(0.0));
        let dot = |a: &Vector, b: &Vector| (0..dimension).map(|d| a[d] * b[d]).sum::<f64>();
        for &[a, b] in &self.pairs {
            let (ma, mb) = (mass[a], mass[b]);
            if ma <= 0.0 || mb <= 0.0 {
                continue;
            }
            let offset: Vector = core::array::from_fn(|d| x[b][d] - x[a][d]);
            let gap = dot(&offset, &normal);
            let (va, vb) = (dot(&v[a], &normal), dot(&v[b], &normal));
            if gap + (vb - va) * dt >= 0.0 {
                continue;
            }
            let va_new = (ma * va + mb * vb + mb * gap / dt) / (ma + mb);
            let vb_new = va_new - gap / dt;
            let impulse = ma * (va_new - va).abs();
            // Tangential velocities and their common (sticking) value.
            let ta: Vector = core::array::from_fn(|d| v[a][d] - va * normal[d]);
            let tb: Vector = core::array::from_fn(|d| v[b][d] - vb * normal[d]);
            let slip: Vector = core::array::from_fn(|d| tb[d] - ta[d]);
            let slip_speed = dot(&slip, &slip).sqrt();
            let reduced = ma * mb / (ma + mb);
            let fraction = if slip_speed > 0.0 {
                (self.friction * impulse / (reduced * slip_speed)).min(1.0)
            } else {
                0.0
            };
            let (before_a, before_b) = (v[a], v[b]);
            for d in 0..dimension {
                // Each node moves `fraction` of the way to the common tangential velocity.
                let common = (ma * ta[d] + mb * tb[d]) / (ma + mb);
                let ta_new = ta[d] + fraction * (common - ta[d]);
                let tb_new = tb[d] + fraction * (common - tb[d]);
                v[a][d] = ta_new + va_new * normal[d];
                v[b][d] = tb_new + vb_new * normal[d];
                velocity_change[a][d] += v[a][d] - before_a[d];
                velocity_change[b][d] += v[b][d] - before_b[d];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_closing_pair_meets_with_its_momentum_and_friction_bounded() {
        // GOAL: the pair's impact conserves momentum in both directions, closes the gap, and
        //       friction slows the slip by at most mu times the normal impulse.
        // SETUP: a (1 kg) at rest; b (3 kg) 1 mm above it, moving down at 20 m/s and sideways
        //        at 1 m/s; dt 1e-4 (b would cross by 1 mm); mu 0.1.
        // REFERENCE: normal: v_a' = (0 - 60 + 3 * 10) / 4 = -7.5, v_b' = -7.5 - 10 = -17.5 m/s
        //            (new gap 0); impulse on a 7.5 N s; sticking needs reduced mass 0.75 x
        //            slip 1 = 0.75 N s > mu x 7.5 = 0.75: exactly sticks (fraction 1), both at
        //            the common 0.75 m/s; momentum (x: 3, z: -60) kept.
        let contact = NodeToNodeContact {
            pairs: vec![[0, 1]],
            normal: vec![0.0, 0.0, 1.0],
            friction: 0.1,
        };
        let x = vec![[0.0; 3], [0.0, 0.0, 1e-3]];
        let mut v = vec![[0.0; 3], [1.0, 0.0, -20.0]];
        let mut change = vec![[0.0; 3]; 2];
        let mass = [1.0, 3.0];
        contact.check(2).unwrap();
        contact.resolve(&mass, &x, &mut v, &mut change, 1e-4, 3);
        assert!(
            (v[0][2] + 7.5).abs() < 1e-12 && (v[1][2] + 17.5).abs() < 1e-12,
            "{v:?}"
        );
        let momentum = |k: usize| mass[0] * v[0][k] + mass[1] * v[1][k];
        assert!((momentum(2) + 60.0).abs() < 1e-12 && (momentum(0) - 3.0).abs() < 1e-12);
        assert!((v[0][0] - 0.75).abs() < 1e-12 && (v[1][0] - 0.75).abs() < 1e-12);
        // A pair moving apart is left alone.
        let mut apart = vec![[0.0; 3], [0.0, 0.0, 1.0]];
        contact.resolve(&mass, &x, &mut apart, &mut change, 1e-4, 3);
        assert_eq!(apart, vec![[0.0; 3], [0.0, 0.0, 1.0]]);
        // A node in two pairs is refused.
        let shared = NodeToNodeContact {
            pairs: vec![[0, 1], [1, 2]],
            ..contact
        };
        assert!(shared.check(3).is_err());
    }
}
