//! Progress of a long loop (episodes, VQA questions). On a terminal, a bar with its ETA. Where
//! stderr is a file or a pipe (a batch job's log, `nohup`), a bar draws nothing at all, so there a
//! plain line is written now and then instead: a run of hours is not silent until it ends.

use std::io::{IsTerminal, Write};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};

use super::lock;

/// How often a log line is written at most (one is written at the first item after this long).
const LOG_EVERY: Duration = Duration::from_secs(60);

/// A progress display, shared by the worker threads.
pub(crate) struct Progress {
    kind: Kind,
}

enum Kind {
    Hidden,
    Bar(ProgressBar),
    Lines(Mutex<Lines>),
}

/// The log form's state.
struct Lines {
    out: Box<dyn Write + Send>,
    /// What is counted ("episodes").
    unit: &'static str,
    len: u64,
    done: u64,
    note: String,
    start: Instant,
    last: Instant,
    every: Duration,
}

impl Progress {
    /// Progress over `len` items of `unit` on stderr: hidden when `quiet`, a bar on a
    /// terminal, else a log line at most every minute.
    pub(crate) fn stderr(len: u64, unit: &'static str, quiet: bool) -> Progress {
        if quiet {
            return Progress { kind: Kind::Hidden };
        }
        if std::io::stderr().is_terminal() {
            let bar = ProgressBar::new(len);
            if let Ok(style) = ProgressStyle::with_template("{elapsed_precise} [{bar:30}] {pos}/{len} ETA {eta} {msg}") {
                bar.set_style(style.progress_chars("=> "));
            }
            bar.enable_steady_tick(Duration::from_millis(500));
            return Progress { kind: Kind::Bar(bar) };
        }
        Progress::lines(Box::new(std::io::stderr()), len, unit, LOG_EVERY)
    }

    /// The log form, written to `out` at most every `every`.
    fn lines(out: Box<dyn Write + Send>, len: u64, unit: &'static str, every: Duration) -> Progress {
        let now = Instant::now();
        Progress { kind: Kind::Lines(Mutex::new(Lines { out, unit, len, done: 0, note: String::new(), start: now, last: now, every })) }
    }

    /// One more item done.
    pub(crate) fn inc(&self) {
        match &self.kind {
            Kind::Hidden => {}
            Kind::Bar(bar) => bar.inc(1),
            Kind::Lines(lines) => {
                let mut l = lock(lines);
                l.done += 1;
                let now = Instant::now();
                if now.duration_since(l.last) >= l.every && l.done < l.len {
                    l.last = now;
                    let line = l.line(now);
                    // A log that cannot be written loses its progress lines, nothing else.
                    let _ = writeln!(l.out, "{line}");
                }
            }
        }
    }

    /// A short note shown beside the count (the errors so far).
    pub(crate) fn note(&self, note: String) {
        match &self.kind {
            Kind::Hidden => {}
            Kind::Bar(bar) => bar.set_message(note),
            Kind::Lines(lines) => lock(lines).note = note,
        }
    }

    /// Ends the display (the caller prints its own summary next).
    pub(crate) fn finish(&self) {
        if let Kind::Bar(bar) = &self.kind {
            bar.finish();
        }
    }
}

impl Lines {
    fn line(&self, now: Instant) -> String {
        let elapsed = now.duration_since(self.start);
        let left = elapsed.mul_f64((self.len - self.done) as f64 / self.done as f64);
        let percent = 100 * self.done / self.len.max(1);
        let mut line = format!(
            "  {}/{} {} ({percent} %), {} elapsed, about {} left",
            self.done,
            self.len,
            self.unit,
            clock(elapsed),
            clock(left)
        );
        if !self.note.is_empty() {
            line += &format!("; {}", self.note);
        }
        line
    }
}

/// `1h02m03s`, `2m03s` or `3s`.
fn clock(d: Duration) -> String {
    let s = d.as_secs();
    match (s / 3600, s / 60 % 60, s % 60) {
        (0, 0, s) => format!("{s}s"),
        (0, m, s) => format!("{m}m{s:02}s"),
        (h, m, s) => format!("{h}h{m:02}m{s:02}s"),
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;

    /// A writer whose bytes the test reads back.
    #[derive(Clone, Default)]
    struct Shared(Arc<Mutex<Vec<u8>>>);

    impl Write for Shared {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            lock(&self.0).extend_from_slice(buf);
            Ok(buf.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_log_gets_a_line_per_interval_with_count_eta_and_note_but_none_for_the_last_item() {
        let out = Shared::default();
        let p = Progress::lines(Box::new(out.clone()), 4, "episodes", Duration::ZERO);
        p.inc();
        p.note("errors: 1".into());
        p.inc();
        p.inc();
        p.inc();
        p.finish();
        let text = String::from_utf8(lock(&out.0).clone()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3, "{text}");
        assert!(lines[0].starts_with("  1/4 episodes (25 %), ") && lines[0].contains(" elapsed, about "), "{text}");
        assert!(!lines[0].contains("errors"), "{text}");
        assert!(lines[2].starts_with("  3/4 episodes (75 %), ") && lines[2].ends_with("; errors: 1"), "{text}");
    }

    #[test]
    fn a_log_stays_quiet_within_its_interval() {
        let out = Shared::default();
        let p = Progress::lines(Box::new(out.clone()), 100, "questions", Duration::from_secs(3600));
        for _ in 0..50 {
            p.inc();
        }
        assert!(lock(&out.0).is_empty());
    }

    #[test]
    fn clock_reads_hours_minutes_and_seconds() {
        assert_eq!(clock(Duration::from_secs(3)), "3s");
        assert_eq!(clock(Duration::from_secs(123)), "2m03s");
        assert_eq!(clock(Duration::from_secs(3723)), "1h02m03s");
    }
}
