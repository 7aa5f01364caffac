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
            let name = arg.unwrap_or_else(|| "argument".into());
            let value = ctx(ContextKind::InvalidValue).unwrap_or_default();
            let allowed = match ctx(ContextKind::ValidValue).filter(|v| !v.is_empty()) {
                Some(v) => format!("one of: {v}"),
                None => match std::error::Error::source(e).and_then(|s| s.downcast_ref::<Allowed>()) {
                    Some(a) => a.0.clone(),
                    // no value after the flag: what its parser allows (issue 69: "allowed one of: ")
                    None if value.is_empty() => {
                        allowed_of(command, &name).unwrap_or_else(|| "a non-empty value".into())
                    }
                    None => match std::error::Error::source(e) {
                        Some(src) => format!("a value of the option's type ({src})"),
                        None => "a value of the option's type".into(),
                    },
                },
            };
            let value = if value.is_empty() { "''".to_string() } else { value };
            format!("invalid {name} = {value}: allowed {allowed}")
        }
        ErrorKind::ArgumentConflict => {
            let name = arg.unwrap_or_else(|| "argument".into());
            let prior = ctx(ContextKind::PriorArg).map(|a| arg_name(&a)).unwrap_or_default();
            format!("invalid {name} = {name} {prior}: allowed one of {name}, {prior}, not both")
        }
        // nothing written is shown as `''`, as an empty value (issue 69: "(missing)")
        ErrorKind::MissingRequiredArgument => format!(
            "invalid {} = '': allowed a value; required and not given",
            arg.unwrap_or_else(|| "argument".into())
        ),
        ErrorKind::UnknownArgument => format!(
            "invalid argument = {}: allowed the command's options (see --help)",
            arg.unwrap_or_else(|| "''".into())
        ),
        ErrorKind::InvalidSubcommand => {
            let value = ctx(ContextKind::InvalidSubcommand).unwrap_or_default();
            format!("invalid command = {value}: allowed {}", allowed_commands(command))
        }
        ErrorKind::MissingSubcommand | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            format!("invalid command = '': allowed {}", allowed_commands(command))
        }
        _ => {
            let first = e.render().to_string();
            let first = first.lines().next().unwrap_or("").trim_start_matches("error: ").to_string();
            let name = arg.unwrap_or_else(|| "arguments".into());
            let value = ctx(ContextKind::InvalidValue).filter(|v| !v.is_empty()).unwrap_or_else(|| name.clone());
            format!("invalid {name} = {value}: allowed the usage shown by --help ({first})")
        }
    };
    Some(line)
}

/// What a flag allows, carried from its value parser's error into the one
/// line (issue 69: integer flags given `-1`, `abc`, `1e3` or `3x` said
/// "allowed a value of the option's type" with no range).
#[derive(Debug)]
pub struct Allowed(pub String);

impl std::fmt::Display for Allowed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Allowed {}

/// The parser of a whole-number flag: digits only; anything else is refused
/// with "a whole number `range`" (the range itself is checked after
/// parsing, where the bound may depend on the input, e.g. the mesh).
pub fn whole_number(text: &str, range: &str) -> Result<usize, Allowed> {
    text.parse::<usize>().map_err(|_| Allowed(format!("a whole number {range}")))
}

/// What `flag` (e.g. `--samples`) of `command` or one of its subcommands
/// allows, as its value parser states it for an empty value.
fn allowed_of(command: &clap::Command, flag: &str) -> Option<String> {
    let long = flag.strip_prefix("--")?;
    let commands = std::iter::once(command).chain(command.get_subcommands());
    let owner = commands.into_iter().find(|c| c.get_arguments().any(|a| a.get_long() == Some(long)))?;
    // the flag given an empty value: its parser's error, before any check of the rest
    let err = owner.clone().no_binary_name(true).try_get_matches_from([flag, ""]).err()?;
    let allowed = std::error::Error::source(&err)?.downcast_ref::<Allowed>()?;
    Some(allowed.0.clone())
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
