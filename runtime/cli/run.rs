//! `magbubble run` (scaffold: replaced by its owner).

/// Arguments of `magbubble run`.
#[derive(Debug, clap::Args)]
pub struct RunArgs {}

pub fn run(_args: &RunArgs) -> anyhow::Result<()> {
    anyhow::bail!("`magbubble run` is not built yet")
}
