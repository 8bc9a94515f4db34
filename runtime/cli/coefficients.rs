//! `magbubble coefficients` (scaffold: replaced by its owner).

/// Arguments of `magbubble coefficients`.
#[derive(Debug, clap::Args)]
pub struct CoefficientsArgs {}

pub fn run(_args: &CoefficientsArgs) -> anyhow::Result<()> {
    anyhow::bail!("`magbubble coefficients` is not built yet")
}
