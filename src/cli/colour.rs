//! `--color`: when diagnostics and clap's own messages are coloured.

use std::io::{self, IsTerminal};

use clap::ValueEnum;

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum ColorArg {
    Auto,
    Always,
    Never,
}

/// The `--color` of this run, set once in `main`.
pub(crate) static COLOR: std::sync::OnceLock<ColorArg> = std::sync::OnceLock::new();

/// Whether to colour what goes to a stream that is (`terminal`) a terminal: `--color always`
/// or `never` as said; `auto` as <https://no-color.org> and <https://bixense.com/clicolors/>
/// say, in anstream's order: NO_COLOR (set, not empty) never, CLICOLOR_FORCE (set, not `0`)
/// always, CLICOLOR=0 or TERM=dumb never, else a terminal.
pub(crate) fn colour_wanted(
    choice: ColorArg,
    terminal: bool,
    env: impl Fn(&str) -> Option<std::ffi::OsString>,
) -> bool {
    let set = |name: &str| env(name).filter(|v| !v.is_empty());
    match choice {
        ColorArg::Always => true,
        ColorArg::Never => false,
        ColorArg::Auto => {
            if set("NO_COLOR").is_some() {
                false
            } else if set("CLICOLOR_FORCE").is_some_and(|v| v != "0") {
                true
            } else if env("CLICOLOR").is_some_and(|v| v == "0")
                || env("TERM").is_some_and(|v| v == "dumb")
            {
                false
            } else {
                terminal
            }
        }
    }
}

/// Whether to colour stderr (`false`: stdout).
pub(crate) fn colour(stderr: bool) -> bool {
    let terminal = if stderr {
        io::stderr().is_terminal()
    } else {
        io::stdout().is_terminal()
    };
    colour_wanted(
        COLOR.get().copied().unwrap_or(ColorArg::Auto),
        terminal,
        |name| std::env::var_os(name),
    )
}

/// `--color WHEN` from the raw arguments, for clap's own help and errors (printed before
/// the arguments are parsed).
pub(crate) fn colour_argument(args: &[std::ffi::OsString]) -> Option<ColorArg> {
    let mut args = args.iter().map(|a| a.to_string_lossy());
    while let Some(arg) = args.next() {
        if arg == "--" {
            break;
        }
        let value = match arg.strip_prefix("--color") {
            Some("") => args.next().map(|v| v.into_owned()),
            Some(rest) => rest.strip_prefix('=').map(str::to_string),
            None => continue,
        };
        return value.and_then(|v| ColorArg::from_str(&v, true).ok());
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colour_follows_the_flag_then_no_color_then_clicolor_force_then_the_terminal() {
        let env = |vars: &'static [(&'static str, &'static str)]| {
            move |name: &str| {
                vars.iter()
                    .find(|(n, _)| *n == name)
                    .map(|(_, v)| std::ffi::OsString::from(v))
            }
        };
        use ColorArg::{Always, Auto, Never};
        assert!(colour_wanted(Auto, true, env(&[])));
        assert!(!colour_wanted(Auto, false, env(&[])));
        assert!(!colour_wanted(Auto, true, env(&[("NO_COLOR", "1")])));
        // An empty NO_COLOR is no request.
        assert!(colour_wanted(Auto, true, env(&[("NO_COLOR", "")])));
        assert!(colour_wanted(Auto, false, env(&[("CLICOLOR_FORCE", "1")])));
        assert!(!colour_wanted(Auto, false, env(&[("CLICOLOR_FORCE", "0")])));
        assert!(!colour_wanted(
            Auto,
            false,
            env(&[("CLICOLOR_FORCE", "1"), ("NO_COLOR", "1")])
        ));
        assert!(!colour_wanted(Auto, true, env(&[("CLICOLOR", "0")])));
        assert!(!colour_wanted(Auto, true, env(&[("TERM", "dumb")])));
        assert!(colour_wanted(Always, false, env(&[("NO_COLOR", "1")])));
        assert!(!colour_wanted(Never, true, env(&[("CLICOLOR_FORCE", "1")])));
    }

    #[test]
    fn colour_is_found_in_the_raw_arguments() {
        let args = |a: &[&str]| a.iter().map(std::ffi::OsString::from).collect::<Vec<_>>();
        assert_eq!(
            colour_argument(&args(&["ncthread", "--color", "never", "-h"])),
            Some(ColorArg::Never)
        );
        assert_eq!(
            colour_argument(&args(&["ncthread", "check", "--color=ALWAYS"])),
            Some(ColorArg::Always)
        );
        assert_eq!(
            colour_argument(&args(&["ncthread", "--", "--color=always"])),
            None
        );
        assert_eq!(colour_argument(&args(&["ncthread", "-h"])), None);
    }
}
