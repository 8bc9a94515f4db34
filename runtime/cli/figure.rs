//! `magbubble figure` (scaffold: replaced by its owner).

/// Arguments of `magbubble figure`.
#[derive(Debug, clap::Args)]
pub struct FigureArgs {}

pub fn run(_args: &FigureArgs) -> anyhow::Result<()> {
    anyhow::bail!("`magbubble figure` is not built yet")
}
