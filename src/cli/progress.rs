//! The CLI's progress sink: an indicatif bar on stderr, drawn only when
//! stderr is a terminal (piped or redirected output gets no control codes).

use std::io::IsTerminal;
use std::sync::{Arc, Mutex};

use crate::bayes::{Control, Progress};

/// One bar per phase, `{bar:40} {pos}/{len} <unit> ({eta})`, cleared when the
/// phase ends.
#[derive(Default)]
pub struct TerminalBar {
    bar: Mutex<Option<indicatif::ProgressBar>>,
}

impl TerminalBar {
    /// A control drawing this bar when stderr is a terminal; otherwise one
    /// that reports nothing.
    pub fn control() -> Control {
        if std::io::stderr().is_terminal() {
            Control::with_progress(Arc::new(TerminalBar::default()))
        } else {
            Control::default()
        }
    }
}

impl Progress for TerminalBar {
    fn start(&self, unit: &'static str, total: u64) {
        let pb = indicatif::ProgressBar::new(total);
        pb.set_style(
            indicatif::ProgressStyle::with_template(&format!("{{bar:40}} {{pos}}/{{len}} {unit} ({{eta}})"))
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        if let Some(old) = self.bar.lock().expect("no panic holds the lock").replace(pb) {
            old.finish_and_clear();
        }
    }

    fn advance(&self, n: u64) {
        if let Some(pb) = self.bar.lock().expect("no panic holds the lock").as_ref() {
            pb.inc(n);
        }
    }

    fn finish(&self) {
        if let Some(pb) = self.bar.lock().expect("no panic holds the lock").take() {
            pb.finish_and_clear();
        }
    }
}
