//! The work behind the `vifo` subcommands, as a library so tests can drive it directly.

pub mod bench;
pub mod expert;
pub mod look;
pub mod render;
pub mod start;
pub mod xval;

/// An error with its causes, as `vifo` prints it: each cause after a colon, except where the
/// message so far already ends with it (many errors repeat their source's text in their own,
/// and `{:#}` would print it twice: "x.png: No such file …: No such file …").
pub fn error_message(err: &anyhow::Error) -> String {
    let mut message = String::new();
    for cause in err.chain() {
        let text = cause.to_string();
        if message.is_empty() {
            message = text;
        } else if !message.ends_with(&text) {
            message.push_str(": ");
            message.push_str(&text);
        }
    }
    message
}

/// The exit status of a program that a closed pipe ended (128 + SIGPIPE), as the shell shows it.
pub const CLOSED_OUTPUT_STATUS: i32 = 141;

/// Makes a closed standard output or error end the program quietly, as it ends C tools:
/// `vifo cues list --ids | head` must not print a panic. Rust ignores SIGPIPE, so `println!`
/// panics on the broken pipe; that panic alone exits with [`CLOSED_OUTPUT_STATUS`] (results
/// already written are kept, as after any interruption), and every other panic goes to the
/// default hook. SIGPIPE stays ignored, so a policy server's closed socket is still an error of
/// its episode, not the end of the run.
pub fn exit_quietly_when_output_closes() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let payload = info.payload();
        let message = payload.downcast_ref::<String>().map(String::as_str).or_else(|| payload.downcast_ref::<&str>().copied()).unwrap_or("");
        let printing = message.starts_with("failed printing to stdout") || message.starts_with("failed printing to stderr");
        if printing && message.to_ascii_lowercase().contains("broken pipe") {
            std::process::exit(CLOSED_OUTPUT_STATUS);
        }
        default(info);
    }));
}

#[cfg(test)]
mod tests {
    use super::error_message;

    /// Like many of the workspace's errors: its text holds its source's.
    #[derive(Debug)]
    struct Repeats {
        path: String,
        source: std::io::Error,
    }

    impl std::fmt::Display for Repeats {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            write!(f, "{}: {}", self.path, self.source)
        }
    }

    impl std::error::Error for Repeats {
        fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
            Some(&self.source)
        }
    }

    #[test]
    fn a_cause_already_in_the_message_is_printed_once_and_others_are_kept() {
        let io = || std::io::Error::new(std::io::ErrorKind::NotFound, "no such file");
        let err = anyhow::Error::new(Repeats { path: "out/x.png".into(), source: io() });
        assert_eq!(error_message(&err), "out/x.png: no such file");
        let err = anyhow::Error::new(io()).context("reading scene.json");
        assert_eq!(error_message(&err), "reading scene.json: no such file");
        let err = anyhow::Error::new(Repeats { path: "a".into(), source: io() }).context("saving frame 3");
        assert_eq!(error_message(&err), "saving frame 3: a: no such file");
    }
}
