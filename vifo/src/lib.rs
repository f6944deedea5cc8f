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
