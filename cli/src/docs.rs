//! `crmorph completions SHELL` and `crmorph man [COMMAND]`: shell completion scripts and roff
//! manual pages, generated from the same clap definition that parses the command line, so they
//! never fall behind it. Both print to stdout, for packagers and users to redirect where their
//! system looks (`crmorph completions bash > …/completions/crmorph`, `crmorph man > crmorph.1`).

use std::io::Write;

use anyhow::{Context, Result};
use clap::{Args, CommandFactory};
use clap_complete::Shell;

use crate::commands::Usage;
use crate::Cli;

/// `crmorph completions`: a completion script for one shell.
#[derive(Debug, Clone, Args)]
pub(crate) struct CompletionsArgs {
    /// The shell to complete in.
    #[arg(value_enum)]
    pub(crate) shell: Shell,
}

/// `crmorph man`: a manual page.
#[derive(Debug, Clone, Args)]
pub(crate) struct ManArgs {
    /// A command whose own page to print (crmorph-COMMAND(1)); default: crmorph(1), which
    /// lists every command.
    pub(crate) command: Option<String>,
}

/// Writes the completion script for `a.shell` to `out`.
pub(crate) fn completions(a: &CompletionsArgs, out: &mut impl Write) -> Result<()> {
    let mut buf = Vec::new();
    clap_complete::generate(a.shell, &mut Cli::command(), "crmorph", &mut buf);
    out.write_all(&buf).context("cannot write to stdout")
}

/// Writes the roff manual page of crmorph, or of one of its commands, to `out`.
pub(crate) fn man(a: &ManArgs, out: &mut impl Write) -> Result<()> {
    let mut cmd = Cli::command();
    // Building names each subcommand crmorph-COMMAND (its display name), the name of its page,
    // as git's and cargo's are named, and its synopsis `crmorph COMMAND` (its bin name).
    cmd.build();
    let page = match &a.command {
        None => cmd,
        Some(name) => {
            let names: Vec<String> = cmd
                .get_subcommands()
                .filter(|c| c.get_name() != "help")
                .map(|c| c.get_name().to_string())
                .collect();
            let Some(sub) = cmd.find_subcommand(name).cloned() else {
                return Err(Usage(format!(
                    "crmorph has no command '{name}'; it has {}",
                    names.join(", ")
                ))
                .into());
            };
            sub
        }
    };
    // The conventions (the top-level `after_help`) as their own section, preformatted: roff
    // would otherwise run the table's lines together.
    let conventions = page.get_after_help().map(|h| h.to_string());
    let page = page.after_help(None::<&str>);
    let mut buf = Vec::new();
    clap_mangen::Man::new(page)
        .render(&mut buf)
        .context("cannot render the manual page")?;
    let mut text = String::from_utf8(buf).context("the manual page is not UTF-8")?;
    if let Some(conventions) = conventions {
        let mut section = roff::Roff::new();
        section
            .control("SH", ["MARKUP CONVENTIONS"])
            .control("nf", []);
        for line in conventions.lines() {
            section.text([roff::roman(line)]);
        }
        section.control("fi", []);
        let at = text.find("\n.SH VERSION").map_or(text.len(), |i| i + 1);
        text.insert_str(at, &section.to_roff());
    }
    out.write_all(text.as_bytes())
        .context("cannot write to stdout")
}

#[cfg(test)]
mod tests {
    use super::*;

    const COMMANDS: [&str; 6] = [
        "morph",
        "frame",
        "inspect",
        "skeleton",
        "completions",
        "man",
    ];

    /// How each shell's script offers the command `c` (as `clap_complete` writes them).
    fn offers(shell: Shell, c: &str) -> String {
        match shell {
            Shell::Bash => format!("crmorph,{c})"),
            Shell::Zsh => format!("'{c}:"),
            Shell::Fish => format!("-a \"{c}\""),
            Shell::Elvish => format!("cand {c} '"),
            _ => format!("[CompletionResult]::new('{c}', '{c}'"),
        }
    }

    #[test]
    fn every_shell_gets_a_script_that_offers_the_commands() {
        for shell in [
            Shell::Bash,
            Shell::Zsh,
            Shell::Fish,
            Shell::Elvish,
            Shell::PowerShell,
        ] {
            let mut out = Vec::new();
            completions(&CompletionsArgs { shell }, &mut out).unwrap();
            let text = String::from_utf8(out).unwrap();
            for c in COMMANDS {
                assert!(text.contains(&offers(shell, c)), "{shell}: no '{c}'");
            }
            assert!(!text.contains(&offers(shell, "nonsense")), "{shell}");
            // The commands' options complete too.
            assert!(text.contains("frames-dir"), "{shell}");
        }
    }

    #[test]
    fn the_manual_pages_list_the_commands_and_their_options() {
        let page = |command: Option<&str>| {
            let mut out = Vec::new();
            man(
                &ManArgs {
                    command: command.map(str::to_string),
                },
                &mut out,
            )
            .unwrap();
            String::from_utf8(out).unwrap()
        };
        let top = page(None);
        assert!(top.contains(".TH crmorph 1"), "{}", &top[..200]);
        for c in COMMANDS {
            assert!(
                top.contains(&format!("crmorph\\-{c}(1)")),
                "crmorph(1) does not list '{c}'"
            );
        }
        // The markup conventions, one line each (not run together).
        let conventions = &top[top.find(".SH \"MARKUP CONVENTIONS\"\n.nf\n").unwrap()..];
        assert!(conventions.contains("\n  feature\\-NAME "), "{conventions}");
        assert!(conventions.find(".fi").unwrap() < conventions.find(".SH VERSION").unwrap());
        let morph = page(Some("morph"));
        assert!(morph.contains(".TH crmorph-morph 1"), "{}", &morph[..200]);
        assert!(morph.contains("\\fBcrmorph morph\\fR"), "synopsis");
        assert!(morph.contains("frames\\-dir"));
        assert!(!morph.contains("MARKUP CONVENTIONS"));
        assert!(man(
            &ManArgs {
                command: Some("nonsense".into())
            },
            &mut Vec::new()
        )
        .unwrap_err()
        .downcast_ref::<Usage>()
        .is_some());
    }
}
