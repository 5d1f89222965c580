//! Local polish from the best point of a Bayesian instance: Nelder-Mead (Nelder & Mead 1965;
//! standard coefficients: reflection 1, expansion 2, contraction 1/2, shrink 1/2) in the unit
//! cube of the constants, points clamped to the box, failed or infeasible candidates scored
//! `+inf`. Written as an ask/tell state machine that proposes one point at a time, so every
//! candidate goes through the same logging and resuming as the Bayesian ones.

/// Where the method is in its iteration.
#[derive(Clone, Debug)]
enum Phase {
    /// Evaluating vertex `k` of the initial simplex.
    Initial(usize),
    /// Waiting for the reflected point.
    Reflect,
    /// Waiting for the expanded point; the reflected point and value are kept.
    Expand(Vec<f64>, f64),
    /// Waiting for the outside contraction; the reflected value is kept.
    ContractOutside(f64),
    /// Waiting for the inside contraction.
    ContractInside,
    /// Re-evaluating vertex `k` after a shrink.
    Shrink(usize),
}

/// Nelder-Mead in the unit cube `[0, 1]^n`.
#[derive(Clone, Debug)]
pub struct NelderMead {
    simplex: Vec<Vec<f64>>,
    values: Vec<f64>,
    phase: Phase,
    pending: Option<Vec<f64>>,
}

fn clamp_unit(x: Vec<f64>) -> Vec<f64> {
    x.into_iter().map(|v| v.clamp(0.0, 1.0)).collect()
}

impl NelderMead {
    /// Start from `start` (unit coordinates) whose value is `value`, with an initial simplex of
    /// edge `step` (towards the interior where `start` lies near a bound).
    pub fn new(start: &[f64], value: f64, step: f64) -> Self {
        let mut simplex = vec![start.to_vec()];
        for i in 0..start.len() {
            let mut vertex = start.to_vec();
            vertex[i] = if start[i] + step <= 1.0 {
                start[i] + step
            } else {
                start[i] - step
            };
            simplex.push(vertex);
        }
        let mut values = vec![f64::INFINITY; simplex.len()];
        values[0] = value;
        Self {
            simplex,
            values,
            phase: Phase::Initial(1),
            pending: None,
        }
    }

    fn order(&mut self) {
        let mut pairs: Vec<(Vec<f64>, f64)> =
            self.simplex.drain(..).zip(self.values.drain(..)).collect();
        pairs.sort_by(|a, b| a.1.total_cmp(&b.1));
        for (x, v) in pairs {
            self.simplex.push(x);
            self.values.push(v);
        }
    }

    fn centroid(&self) -> Vec<f64> {
        let n = self.simplex.len() - 1;
        (0..self.simplex[0].len())
            .map(|d| self.simplex[..n].iter().map(|x| x[d]).sum::<f64>() / n as f64)
            .collect()
    }

    fn along(&self, coefficient: f64) -> Vec<f64> {
        let centroid = self.centroid();
        let worst = &self.simplex[self.simplex.len() - 1];
        clamp_unit(
            centroid
                .iter()
                .zip(worst)
                .map(|(c, w)| c + coefficient * (c - w))
                .collect(),
        )
    }

    /// The next point to evaluate (unit coordinates).
    pub fn ask(&mut self) -> Vec<f64> {
        let point = match &self.phase {
            Phase::Initial(k) | Phase::Shrink(k) => self.simplex[*k].clone(),
            Phase::Reflect => self.along(1.0),
            Phase::Expand(..) => self.along(2.0),
            Phase::ContractOutside(..) => self.along(0.5),
            Phase::ContractInside => self.along(-0.5),
        };
        self.pending = Some(point.clone());
        point
    }

    fn start_iteration(&mut self) {
        self.order();
        self.phase = Phase::Reflect;
    }

    fn replace_worst(&mut self, x: Vec<f64>, value: f64) {
        let last = self.simplex.len() - 1;
        self.simplex[last] = x;
        self.values[last] = value;
        self.start_iteration();
    }

    fn shrink(&mut self) {
        let best = self.simplex[0].clone();
        for vertex in self.simplex.iter_mut().skip(1) {
            *vertex = vertex
                .iter()
                .zip(&best)
                .map(|(v, b)| b + 0.5 * (v - b))
                .collect();
        }
        self.phase = Phase::Shrink(1);
    }

    /// The value of the last asked point (`None`: failed or infeasible).
    pub fn tell(&mut self, value: Option<f64>) {
        let value = value.filter(|v| v.is_finite()).unwrap_or(f64::INFINITY);
        let Some(x) = self.pending.take() else { return };
        let n = self.simplex.len() - 1;
        match std::mem::replace(&mut self.phase, Phase::Reflect) {
            Phase::Initial(k) | Phase::Shrink(k) => {
                self.values[k] = value;
                if k < n {
                    self.phase = Phase::Initial(k + 1);
                } else {
                    self.start_iteration();
                }
            }
            Phase::Reflect => {
                let (best, second_worst, worst) =
                    (self.values[0], self.values[n - 1], self.values[n]);
                if value < best {
                    self.phase = Phase::Expand(x, value);
                } else if value < second_worst {
                    self.replace_worst(x, value);
                } else if value < worst {
                    self.phase = Phase::ContractOutside(value);
                } else {
                    self.phase = Phase::ContractInside;
                }
            }
            Phase::Expand(reflected, reflected_value) => {
                if value < reflected_value {
                    self.replace_worst(x, value);
                } else {
                    self.replace_worst(reflected, reflected_value);
                }
            }
            Phase::ContractOutside(reflected_value) => {
                if value <= reflected_value {
                    self.replace_worst(x, value);
                } else {
                    self.shrink();
                }
            }
            Phase::ContractInside => {
                if value < self.values[n] {
                    self.replace_worst(x, value);
                } else {
                    self.shrink();
                }
            }
        }
    }

    /// The best vertex and its value.
    pub fn best(&self) -> (Vec<f64>, f64) {
        let k = (0..self.values.len())
            .min_by(|&a, &b| self.values[a].total_cmp(&self.values[b]))
            .unwrap_or(0);
        (self.simplex[k].clone(), self.values[k])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nelder_mead_polishes_a_quadratic_to_its_minimum() {
        // GOAL: the polish converges on a smooth valley. SETUP: an elongated quadratic in
        // the unit square, minimum at (0.3, 0.7), start (0.6, 0.4), 200 evaluations.
        // REFERENCE: distance to the minimum < 1e-4.
        let f = |x: &[f64]| (x[0] - 0.3).powi(2) + 10.0 * (x[1] - 0.7 + 0.5 * (x[0] - 0.3)).powi(2);
        let start = [0.6, 0.4];
        let mut nm = NelderMead::new(&start, f(&start), 0.1);
        for _ in 0..200 {
            let x = nm.ask();
            nm.tell(Some(f(&x)));
        }
        let (x, _) = nm.best();
        assert!(
            ((x[0] - 0.3).powi(2) + (x[1] - 0.7).powi(2)).sqrt() < 1e-4,
            "{x:?}"
        );
    }
}
