//! `magbubble modes` (scaffold: replaced by its owner).

/// Arguments of `magbubble modes`.
#[derive(Debug, clap::Args)]
pub struct ModesArgs {}

pub fn run(_args: &ModesArgs) -> anyhow::Result<()> {
    anyhow::bail!("`magbubble modes` is not built yet")
}
