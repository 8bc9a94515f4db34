//! `run` with `[echo]`: echo.csv (t, then p_s at each point [Pa]) and spectrum.csv
//! (frequency_hz, then the level of each point's echo [dB re 1 Pa]) from the typed tables of
//! [`crate::api::echo::Echo`] (runtime/echo/; docs/model.md, "Echo").

use crate::api::echo::{float_row, Echo};
use crate::api::table::Table;
use crate::output::{CsvWriter, OutputDir};

/// Writes echo.csv and spectrum.csv into `dir`.
pub(super) fn write(dir: &OutputDir, echo: &Echo) -> anyhow::Result<()> {
    write_table(dir, "echo.csv", &echo.echo)?;
    write_table(dir, "spectrum.csv", &echo.spectrum)
}

fn write_table(dir: &OutputDir, name: &str, table: &Table) -> anyhow::Result<()> {
    let mut csv = CsvWriter::create(&dir.join(name), &table.names)?;
    let mut line = Vec::with_capacity(table.names.len());
    for i in 0..table.rows() {
        float_row(table, i, &mut line);
        csv.row(&line);
    }
    csv.commit()?;
    Ok(())
}
