//! `magbubble convergence` (scaffold: replaced by its owner).

/// Arguments of `magbubble convergence`.
#[derive(Debug, clap::Args)]
pub struct ConvergenceArgs {}

pub fn run(_args: &ConvergenceArgs) -> anyhow::Result<()> {
    anyhow::bail!("`magbubble convergence` is not built yet")
}
