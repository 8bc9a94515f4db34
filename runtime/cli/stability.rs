//! `magbubble stability` and `magbubble merge` (scaffold: replaced by its owner).

#[derive(Debug, clap::Args)]
pub struct StabilityArgs {}

#[derive(Debug, clap::Args)]
pub struct MergeArgs {}

pub fn run(_args: &StabilityArgs) -> anyhow::Result<()> {
    anyhow::bail!("`magbubble stability` is not built yet")
}

pub fn merge(_args: &MergeArgs) -> anyhow::Result<()> {
    anyhow::bail!("`magbubble merge` is not built yet")
}
