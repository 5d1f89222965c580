//! Non-local averaging of the damage driver (LS-DYNA `*MAT_NONLOCAL`; Pijaudier-Cabot & Bazant,
//! J. Eng. Mech. 113 (1987) 1512-1533): the remedy seed 001 sec. 5.5 proposes for the drop-weight
//! beam's strain localisation.
//!
//! The damage of a softening model grows with one history variable, the state's
//! `plastic_strain` (K&C's modified plastic strain `lambda`, a J2 model's equivalent plastic
//! strain). With averaging on, each step's local increment of that variable is replaced, in
//! every element of the averaged parts, by the weighted mean of its neighbours' increments:
//!
//! `d lambda_i <- sum_j w_ij V_j d lambda_j / sum_j w_ij V_j`, `w_ij = (1 - r_ij^2 / R^2)^2`
//! for `r_ij < R`
//!
//! with `r_ij` the distance between the reference centroids and `V_j` the reference volumes
//! (the truncated quartic "bell" weight of Bazant & Jirasek, J. Eng. Mech. 128 (2002)
//! 1119-1149). Damage then cannot localise in a band narrower than about the radius `R`
//! whatever the mesh.
//!
//! The averaged value enters the next step's update (the explicit scheme's one-step lag, as
//! in LS-DYNA): the stress of the step that produced the increment is the local one. Each
//! element's mean is a fixed-order sum over its sorted neighbours, so the result does not
//! depend on the thread count.

use super::explicit::Vector;
use super::SolverError;
use rayon::prelude::*;
use std::collections::BTreeMap;
use stoss_kernel::MaterialState;

/// Non-local averaging of the damage driver over a radius.
#[derive(Clone, Debug, PartialEq)]
pub struct NonlocalAveraging {
    /// Averaging radius `R` (m).
    pub radius: f64,
    /// The averaged parts (by index); elements of other parts neither average nor count.
    pub parts: Vec<usize>,
}

/// The averaging of a run: members, neighbour weights and the step's increments.
pub(crate) struct NonlocalField {
    /// The averaged elements, ascending.
    members: Vec<usize>,
    /// `neighbours[start[m]..start[m + 1]]`: member `m`'s neighbours (member indices) and
    /// normalised weights, ascending.
    start: Vec<usize>,
    neighbours: Vec<(usize, f64)>,
    /// Each member's value before the step.
    before: Vec<f64>,
    /// Each member's local increment in the step.
    increments: Vec<f64>,
}

impl NonlocalField {
    /// The weights of `averaging` over elements with reference centroids `centroids`,
    /// volumes `volumes` and parts `part_of`.
    pub(crate) fn new(
        averaging: &NonlocalAveraging,
        centroids: &[Vector],
        volumes: &[f64],
        part_of: impl Fn(usize) -> usize,
    ) -> Result<Self, SolverError> {
        let radius = averaging.radius;
        if !(radius > 0.0 && radius.is_finite()) {
            return Err(SolverError::Model(format!(
                "non-local averaging: the radius must be > 0 (m), not {radius}"
            )));
        }
        let members: Vec<usize> = (0..centroids.len())
            .filter(|&e| averaging.parts.contains(&part_of(e)))
            .collect();
        let cell = |p: &Vector| p.map(|c| libm::floor(c / radius) as i64);
        let mut grid: BTreeMap<[i64; 3], Vec<usize>> = BTreeMap::new();
        for (m, &e) in members.iter().enumerate() {
            grid.entry(cell(&centroids[e])).or_default().push(m);
        }
        let mut start = Vec::with_capacity(members.len() + 1);
        let mut neighbours = Vec::new();
        let mut found: Vec<(usize, f64)> = Vec::new();
        start.push(0);
        for &e in &members {
            let home = cell(&centroids[e]);
            found.clear();
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        let key = [home[0] + dx, home[1] + dy, home[2] + dz];
                        for &m in grid.get(&key).map_or(&[][..], Vec::as_slice) {
                            let other = members[m];
                            let r2: f64 = (0..3)
                                .map(|d| (centroids[other][d] - centroids[e][d]).powi(2))
                                .sum();
                            let q = 1.0 - r2 / (radius * radius);
                            if q > 0.0 {
                                found.push((m, q * q * volumes[other]));
                            }
                        }
                    }
                }
            }
            found.sort_by_key(|&(m, _)| m);
            let total: f64 = found.iter().map(|&(_, w)| w).sum();
            neighbours.extend(found.iter().map(|&(m, w)| (m, w / total)));
            start.push(neighbours.len());
        }
        let count = members.len();
        Ok(Self {
            members,
            start,
            neighbours,
            before: vec![0.0; count],
            increments: vec![0.0; count],
        })
    }

    /// Remember the members' values before a step.
    pub(crate) fn record(&mut self, states: &[MaterialState]) {
        for (value, &e) in self.before.iter_mut().zip(&self.members) {
            *value = states[e].plastic_strain;
        }
    }

    /// Replace each member's increment since [`NonlocalField::record`] by its neighbours'
    /// weighted mean (eroded elements count with no increment).
    pub(crate) fn apply(&mut self, states: &mut [MaterialState], eroded: &[bool]) {
        for (m, &e) in self.members.iter().enumerate() {
            self.increments[m] = if eroded[e] {
                0.0
            } else {
                states[e].plastic_strain - self.before[m]
            };
        }
        let (start, neighbours, increments) = (&self.start, &self.neighbours, &self.increments);
        let averaged: Vec<f64> = (0..self.members.len())
            .into_par_iter()
            .with_min_len(256)
            .map(|m| {
                neighbours[start[m]..start[m + 1]]
                    .iter()
                    .map(|&(k, w)| w * increments[k])
                    .sum::<f64>()
            })
            .collect();
        for ((&e, before), increment) in self.members.iter().zip(&self.before).zip(averaged) {
            if !eroded[e] {
                states[e].plastic_strain = before + increment;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_increment_in_one_element_is_spread_over_the_radius_and_kept_in_total() {
        // GOAL: the averaging spreads a localised increment over the neighbours within R and,
        //       on a uniform grid away from its edges, keeps its volume integral.
        // SETUP: a 9 x 9 x 9 grid of unit cubes (centroids 1 apart), R = 2.5; an increment of 1
        //        in the centre element only.
        // REFERENCE: the centre gets w_00 / sum w (the same normalisation for every element
        //            whose ball lies inside the grid, so the total over all elements is 1);
        //            an element 3 away gets nothing; the sum over elements is 1 to 1e-12.
        let n = 9;
        let mut centroids = Vec::new();
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    centroids.push([i as f64, j as f64, k as f64]);
                }
            }
        }
        let volumes = vec![1.0; centroids.len()];
        let averaging = NonlocalAveraging {
            radius: 2.5,
            parts: vec![0],
        };
        let mut field = NonlocalField::new(&averaging, &centroids, &volumes, |_| 0).unwrap();
        let mut states = vec![MaterialState::initial(293.0); centroids.len()];
        field.record(&states);
        let centre = (4 * n + 4) * n + 4;
        states[centre].plastic_strain = 1.0;
        field.apply(&mut states, &vec![false; centroids.len()]);
        let total: f64 = states.iter().map(|s| s.plastic_strain).sum();
        assert!((total - 1.0).abs() < 1e-12, "{total}");
        assert!(states[centre].plastic_strain < 0.2);
        assert!(states[centre + 1].plastic_strain > 0.0);
        assert_eq!(states[centre + 3].plastic_strain, 0.0);
        // 4/3 pi 2.5^3 = 65 unit cells within the radius.
        assert!(field.neighbours.len() / field.members.len() > 50);
        assert!(NonlocalField::new(
            &NonlocalAveraging {
                radius: 0.0,
                parts: vec![0]
            },
            &centroids,
            &volumes,
            |_| 0
        )
        .is_err());
    }
}
