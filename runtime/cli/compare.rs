//! `magbubble compare` (scaffold: replaced by its owner).

/// Arguments of `magbubble compare`.
#[derive(Debug, clap::Args)]
pub struct CompareArgs {}

pub fn run(_args: &CompareArgs) -> anyhow::Result<()> {
    anyhow::bail!("`magbubble compare` is not built yet")
}
