//! `magbubble scene new|explain|check` (scaffold: replaced by its owner).

#[derive(Debug, clap::Subcommand)]
pub enum SceneCommand {
    /// Print a complete commented default scene.
    New,
}

pub fn run(_c: &SceneCommand) -> anyhow::Result<()> {
    anyhow::bail!("`magbubble scene` is not built yet")
}
