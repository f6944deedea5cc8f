//! Normalisation and tokenisation of instructions.

use super::ParseError;

/// A word of the normalised instruction and the character offset where it starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Token<'a> {
    pub word: &'a str,
    pub start: usize,
}

/// Lower-cases, turns underscores into spaces (LIBERO task names), collapses whitespace and
/// drops one trailing full stop. Anything but ASCII letters, digits, spaces, hyphens and
/// apostrophes is rejected so that odd input is reported instead of silently mis-parsed.
pub fn normalise(instruction: &str) -> Result<String, ParseError> {
    let mut out = String::with_capacity(instruction.len());
    for (i, ch) in instruction.trim().trim_end_matches(['.', '!']).chars().enumerate() {
        let ch = if ch == '_' { ' ' } else { ch.to_ascii_lowercase() };
        if ch.is_whitespace() {
            if !out.ends_with(' ') && !out.is_empty() {
                out.push(' ');
            }
        } else if ch.is_ascii_alphanumeric() || ch == '-' || ch == '\'' {
            out.push(ch);
        } else {
            return Err(ParseError {
                instruction: instruction.to_string(),
                position: i,
                expected: "a letter, digit, space, hyphen or apostrophe".into(),
                found: format!("{ch:?}"),
            });
        }
    }
    if out.is_empty() {
        return Err(ParseError {
            instruction: instruction.to_string(),
            position: 0,
            expected: "an instruction".into(),
            found: "nothing".into(),
        });
    }
    Ok(out)
}

/// Splits a normalised instruction into words with their offsets.
pub fn tokenise(normalised: &str) -> Vec<Token<'_>> {
    let mut tokens = Vec::new();
    let mut start = 0;
    for word in normalised.split(' ') {
        tokens.push(Token { word, start });
        start += word.len() + 1;
    }
    tokens
}

/// The instruction LIBERO derives from a task (BDDL file) name: the text after `SCENE<k>_`
/// for the scene-prefixed suites (libero_10/90), else the whole name; underscores become
/// spaces. Names that are already instructions pass through unchanged.
pub fn instruction_from_task_name(name: &str) -> String {
    let name = name.trim().trim_end_matches(".bddl");
    let body = match name.find("SCENE") {
        Some(at) => {
            let rest = &name[at + "SCENE".len()..];
            let digits = rest.chars().take_while(|c| c.is_ascii_digit()).count();
            if digits > 0 && rest[digits..].starts_with('_') { &rest[digits + 1..] } else { name }
        }
        None => name,
    };
    body.replace('_', " ")
}
