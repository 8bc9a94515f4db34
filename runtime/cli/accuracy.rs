//! `magbubble accuracy` (scaffold: replaced by its owner).

/// Arguments of `magbubble accuracy`.
#[derive(Debug, clap::Args)]
pub struct AccuracyArgs {}

pub fn run(_args: &AccuracyArgs) -> anyhow::Result<()> {
    anyhow::bail!("`magbubble accuracy` is not built yet")
}
