//! A growable history of kernel-driver records (the kernel itself has no heap): what the
//! verification checks, the goldens, the uniaxial experiment and the reports collect.

use stoss_kernel::drivers::{DriverError, HistorySink, Record};

/// Driver records collected in a `Vec`.
#[derive(Clone, Debug, Default)]
pub struct History(pub Vec<Record>);

impl HistorySink for History {
    fn push(&mut self, record: Record) -> Result<(), DriverError> {
        self.0.push(record);
        Ok(())
    }
}
