//! clap's multi-line usage errors reduced to the one line every bad input
//! gets: `invalid <argument> = <value>: allowed <range>` (exit 2).

use clap::error::{ContextKind, ContextValue, ErrorKind};

/// "allowed" of a missing or unknown subcommand: `command`'s subcommands,
/// read from the parser itself so that the list cannot fall behind it.
fn allowed_commands(command: &clap::Command) -> String {
    let names: Vec<&str> = command.get_subcommands().map(|c| c.get_name()).filter(|&n| n != "help").collect();
    format!("one of: {} (see nanobeam --help)", names.join(", "))
}

/// `None` for `--help`/`--version` (print clap's text, exit 0); otherwise
/// the one-line message for exit 2. `command` is the parser that raised `e`
/// (for the subcommands a missing or unknown one may be).
pub fn one_line(e: &clap::Error, command: &clap::Command) -> Option<String> {
    let ctx = |k: ContextKind| e.get(k).map(context_text);
    let arg = ctx(ContextKind::InvalidArg).map(|a| arg_name(&a));
    let line = match e.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => return None,
        ErrorKind::InvalidValue | ErrorKind::ValueValidation => {
            let value = ctx(ContextKind::InvalidValue).unwrap_or_else(|| "(empty)".into());
            let allowed = match ctx(ContextKind::ValidValue) {
                Some(v) => format!("one of: {v}"),
                None => match std::error::Error::source(e) {
                    Some(src) => format!("a value of the option's type ({src})"),
                    None => "a value of the option's type".into(),
                },
            };
            format!("invalid {} = {value}: allowed {allowed}", arg.unwrap_or_else(|| "argument".into()))
        }
        ErrorKind::MissingRequiredArgument => {
            format!("invalid {} = (missing): allowed a value (required)", arg.unwrap_or_else(|| "argument".into()))
        }
        ErrorKind::UnknownArgument => format!(
            "invalid {} = (unknown argument): allowed the command's options (see --help)",
            arg.unwrap_or_else(|| "argument".into())
        ),
        ErrorKind::InvalidSubcommand => {
            let value = ctx(ContextKind::InvalidSubcommand).unwrap_or_default();
            format!("invalid command = {value}: allowed {}", allowed_commands(command))
        }
        ErrorKind::MissingSubcommand | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            format!("invalid command = (missing): allowed {}", allowed_commands(command))
        }
        _ => {
            let first = e.render().to_string();
            let first = first.lines().next().unwrap_or("").trim_start_matches("error: ").to_string();
            format!(
                "invalid {} = ({first}): allowed the usage shown by --help",
                arg.unwrap_or_else(|| "arguments".into())
            )
        }
    };
    Some(line)
}

fn context_text(v: &ContextValue) -> String {
    match v {
        ContextValue::String(s) => s.clone(),
        ContextValue::Strings(v) => v.join(", "),
        ContextValue::StyledStr(s) => s.to_string(),
        ContextValue::StyledStrs(v) => v.iter().map(|s| s.to_string()).collect::<Vec<_>>().join(", "),
        ContextValue::Number(n) => n.to_string(),
        ContextValue::Bool(b) => b.to_string(),
        _ => String::new(),
    }
}

/// `--points <POINTS>` → `--points`; `<BEAM>` → `BEAM`; lists kept.
fn arg_name(a: &str) -> String {
    a.split(", ")
        .map(|one| match one.split_once(" <") {
            Some((flag, _)) => flag.to_string(),
            None => one.trim_matches(|c| c == '<' || c == '>').to_string(),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// Parses the process arguments: help/version print and exit 0, any other
/// error prints its one line and exits 2.
pub fn parse_or_exit<P: clap::Parser>() -> P {
    match P::try_parse() {
        Ok(p) => p,
        Err(e) => match one_line(&e, &P::command()) {
            None => {
                let _ = e.print();
                std::process::exit(0);
            }
            Some(line) => {
                eprintln!("{line}");
                std::process::exit(2);
            }
        },
    }
}

#[cfg(test)]
mod tests {
    use clap::{CommandFactory, Parser};

    use super::one_line;
    use crate::cli::Cli;

    fn line(args: &[&str]) -> String {
        let e = Cli::try_parse_from(args).expect_err("the arguments are invalid");
        one_line(&e, &Cli::command()).expect("not --help")
    }

    #[test]
    fn an_unknown_or_missing_command_lists_every_subcommand_the_parser_has() {
        for l in [line(&["nanobeam", "modl"]), line(&["nanobeam"])] {
            assert_eq!(l.lines().count(), 1, "{l}");
            for name in ["modal", "frf", "calibrate", "diagnose", "identify", "campaign"] {
                assert!(l.contains(name), "{name} missing from: {l}");
            }
            assert!(!l.contains("help,"), "clap's own help subcommand is not a command: {l}");
        }
    }
}
