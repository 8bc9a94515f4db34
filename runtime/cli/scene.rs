//! `magbubble scene new|explain|check`: write a default scene, document every key, validate a
//! scene without running it. All three render the one schema table (`scene::schema`).

use crate::scene::{self, doc, schema};
use std::path::PathBuf;

#[derive(Debug, clap::Subcommand)]
pub enum SceneCommand {
    /// Print a complete commented default scene (redirect it to a file and edit).
    New {
        /// Write to this file instead of stdout (refuses to overwrite).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Print every parameter (or one key or section) with unit, default, range and paper symbol.
    Explain {
        /// A key (`shell.c1`) or a section (`field.coil`); all when omitted.
        key: Option<String>,
    },
    /// Validate a scene (with overrides) and print the resolved parameters; lists every error.
    Check {
        file: PathBuf,
        /// Override a scene key, e.g. --set drive.amplitude=0.3 (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
    },
}

pub fn run(c: &SceneCommand) -> anyhow::Result<()> {
    match c {
        SceneCommand::New { out: None } => out!("{}", doc::default_scene_toml()),
        SceneCommand::New { out: Some(path) } => {
            use std::io::Write;
            let mut f = std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(path)
                .map_err(|e| anyhow::anyhow!("cannot create {}: {e}", path.display()))?;
            f.write_all(doc::default_scene_toml().as_bytes())?;
            noteln!("wrote {}", path.display());
        }
        SceneCommand::Explain { key } => {
            let key = key
                .as_deref()
                .unwrap_or("")
                .trim_matches(|c| c == '[' || c == ']');
            match doc::explain(key) {
                Some(text) => out!("{text}"),
                None => {
                    let sections: Vec<&str> = schema::SCHEMA
                        .iter()
                        .filter(|p| p.kind == schema::Kind::Section)
                        .map(|p| p.key)
                        .collect();
                    anyhow::bail!("no scene key `{key}`; sections: {}", sections.join(", "));
                }
            }
        }
        SceneCommand::Check { file, set } => {
            let scene = scene::load(file, set)?;
            outln!("{}: valid scene", file.display());
            out!("{}", doc::summary(&scene));
        }
    }
    Ok(())
}
