//! `magbubble floquet` (scaffold: replaced by its owner).

/// Arguments of `magbubble floquet`.
#[derive(Debug, clap::Args)]
pub struct FloquetArgs {}

pub fn run(_args: &FloquetArgs) -> anyhow::Result<()> {
    anyhow::bail!("`magbubble floquet` is not built yet")
}
