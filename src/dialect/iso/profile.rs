//! The ISO (LinuxCNC) section of the machine profile (`[iso]`).

use indexmap::IndexMap;
use serde::Deserialize;

use crate::diag::Diagnostic;
use crate::dialect::iso::codes;
use crate::source::SourceFile;

#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct IsoProfile {
    /// Another machine's M code → the user M code (M100–M199) LinuxCNC gets instead.
    pub mcodes: IndexMap<u32, String>,
    pub tool_change: ToolChange,
    /// The block delete switch the program runs with: lines that start with `/` are
    /// skipped when it is on and run when it is off. `None`: not said, so such a line is
    /// refused (whether it runs is the operator's choice). **\[decided\]**
    pub block_delete: Option<BlockDelete>,
    /// Folders that hold subroutine files (`o<name> call` reads `name.ngc` from the first
    /// that has it), LinuxCNC's `SUBROUTINE_PATH`. Relative folders are taken from the
    /// current directory.
    pub subroutine_path: Vec<std::path::PathBuf>,
}

/// LinuxCNC's block delete switch.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BlockDelete {
    /// Lines that start with `/` run (LinuxCNC's default).
    Off,
    /// Lines that start with `/` are skipped.
    On,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ToolChange {
    /// `T9 M6` (LinuxCNC's tool change).
    #[default]
    M6,
    /// `T9` alone (a lathe turret configured to index on T).
    T,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(crate) struct Raw {
    mcodes: Option<IndexMap<String, toml::Spanned<String>>>,
    tool_change: Option<ToolChange>,
    block_delete: Option<BlockDelete>,
    subroutine_path: Option<Vec<std::path::PathBuf>>,
}

/// Reads the `[iso]` section into `p`, reporting each bad value with its line.
pub(crate) fn read(src: &SourceFile, raw: Raw, p: &mut IsoProfile, diags: &mut Vec<Diagnostic>) {
    if let Some(t) = raw.tool_change {
        p.tool_change = t;
    }
    if let Some(b) = raw.block_delete {
        p.block_delete = Some(b);
    }
    if let Some(dirs) = raw.subroutine_path {
        let base = std::path::Path::new(&src.name).parent();
        p.subroutine_path = dirs
            .into_iter()
            .map(|d| match base {
                Some(base) if d.is_relative() => base.join(d),
                _ => d,
            })
            .collect();
    }
    for (key, value) in raw.mcodes.unwrap_or_default() {
        let span = src.span_of(value.span());
        let word = value.into_inner();
        // One of LinuxCNC's user M codes: any other M word has a meaning of LinuxCNC's own
        // (M3 starts the spindle) that the source's code does not have.
        let valid_word = word
            .strip_prefix(['M', 'm'])
            .filter(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
            .and_then(|n| n.parse::<u32>().ok())
            .is_some_and(|n| (100..=199).contains(&n));
        match key.trim_start_matches(['M', 'm']).parse::<u32>() {
            Ok(code) if valid_word => {
                p.mcodes.insert(code, word.to_ascii_uppercase());
            }
            _ => diags.push(
                Diagnostic::new(codes::ISOW_BAD_MAPPING, format!("`{key} = \"{word}\"` is not an M code mapping to one of LinuxCNC's user M codes (M100–M199)"))
                    .at(src, span)
                    .help("write the source M number as the key and one of LinuxCNC's user M codes (M100–M199) as the value, e.g. `42 = \"M142\"`"),
            ),
        }
    }
}
