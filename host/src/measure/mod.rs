//! Measurements extracted from runs, and the state histories of the material points that
//! drive them (strain, rate, temperature, triaxiality, pressure) for the diagnosis.

/// The state of one material point at one time.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StateSample {
    /// Time (s).
    pub time: f64,
    /// Equivalent plastic strain.
    pub plastic_strain: f64,
    /// Plastic strain rate (1/s).
    pub plastic_strain_rate: f64,
    /// Temperature (K).
    pub temperature: f64,
    /// Pressure (Pa).
    pub pressure: f64,
    /// von Mises stress (Pa).
    pub equivalent_stress: f64,
    /// Stress triaxiality `-p/q` (0 when `q = 0`).
    pub triaxiality: f64,
    /// Axial stress (Pa): `sigma_zz` in axisymmetric models, `sigma_xx` in drivers.
    pub axial_stress: f64,
}

impl StateSample {
    /// Sample a kernel state.
    pub fn from_state(
        time: f64,
        state: &stoss_kernel::MaterialState,
        axial_component: usize,
    ) -> Self {
        let q = state.equivalent_stress();
        let p = state.pressure();
        Self {
            time,
            plastic_strain: state.plastic_strain,
            plastic_strain_rate: state.plastic_strain_rate,
            temperature: state.temperature,
            pressure: p,
            equivalent_stress: q,
            triaxiality: if q > 0.0 { -p / q } else { 0.0 },
            axial_stress: state.stress[axial_component],
        }
    }
}

/// The history of one tracked material point.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StateHistory {
    /// What the point is (e.g. `element 12`, `driver`).
    pub label: String,
    /// Samples in time order.
    pub samples: Vec<StateSample>,
}

/// Linear interpolation of `y(x)` on a table sorted by `x`; clamped to the end values.
pub fn interpolate(table: &[(f64, f64)], x: f64) -> f64 {
    match table {
        [] => f64::NAN,
        [only] => only.1,
        _ => {
            if x <= table[0].0 {
                return table[0].1;
            }
            for pair in table.windows(2) {
                if x <= pair[1].0 {
                    let span = pair[1].0 - pair[0].0;
                    let f = if span > 0.0 {
                        (x - pair[0].0) / span
                    } else {
                        1.0
                    };
                    return pair[0].1 + f * (pair[1].1 - pair[0].1);
                }
            }
            table[table.len() - 1].1
        }
    }
}
