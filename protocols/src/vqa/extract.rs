//! Answer extraction as VLMEvalKit does it without a judge model
//! (`vlmeval/utils/matching_util.py`, `can_infer`): first a lone option letter, then a lone
//! option text; a refusal is `Z`; anything else is unparseable. Both `Z` and unparseable
//! answers are scored wrong. Reasoning blocks (`<think>…</think>`) are removed first.

/// What a raw answer says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Extracted {
    /// An option letter, 'A'..='D'.
    Letter(char),
    /// A refusal or an explicit "Z" (VLMEvalKit's none-of-the-above).
    Refused,
    /// No single letter or option text could be found.
    Unparsed,
}

/// VLMEvalKit's refusal strings (`can_infer_option`).
const REFUSALS: [&str; 4] = [
    "Sorry, I can't help with images of people yet.",
    "I can't process this file.",
    "I'm sorry, but without the image provided",
    "Cannot determine the answer",
];

/// Extracts the chosen option from a model's raw text; `options` are the texts of A, B, C, D.
pub fn extract(raw: &str, options: &[String]) -> Extracted {
    let answer = strip_thinking(raw);
    // VLMEvalKit skips the letter search for failed API calls but still tries the texts.
    if !answer.contains("Failed to obtain answer via API")
        && let Some(found) = infer_option(answer, options.len())
    {
        return found;
    }
    infer_text(answer, options).map_or(Extracted::Unparsed, Extracted::Letter)
}

/// The text after the last `</think>`; with an unclosed `<think>`, the text before it.
pub fn strip_thinking(raw: &str) -> &str {
    if let Some(end) = raw.rfind("</think>") {
        &raw[end + "</think>".len()..]
    } else if let Some(start) = raw.find("<think>") {
        &raw[..start]
    } else {
        raw
    }
}

/// `can_infer_option`: replace `.()[],:;!*#{}` by spaces, split on whitespace, and accept
/// exactly one distinct option letter among the tokens (or, with none, exactly one `Z`).
fn infer_option(answer: &str, n_options: usize) -> Option<Extracted> {
    if REFUSALS.iter().any(|r| answer.contains(r)) {
        return Some(Extracted::Refused);
    }
    let cleaned: String = answer.chars().map(|c| if ".()[],:;!*#{}".contains(c) { ' ' } else { c }).collect();
    let tokens: Vec<&str> = cleaned.split_whitespace().collect();
    let letters: Vec<char> =
        ('A'..='Z').take(n_options).filter(|l| tokens.iter().any(|t| t.len() == 1 && t.starts_with(*l))).collect();
    match letters.as_slice() {
        [one] => Some(Extracted::Letter(*one)),
        [] if tokens.iter().filter(|t| **t == "Z").count() == 1 => Some(Extracted::Refused),
        _ => None,
    }
}

/// `can_infer_text`: exactly one option's text (lower-cased) occurs in the answer.
fn infer_text(answer: &str, options: &[String]) -> Option<char> {
    let answer = answer.to_lowercase();
    let hits: Vec<char> = options
        .iter()
        .zip('A'..='Z')
        .filter(|(text, _)| answer.contains(&text.to_lowercase()))
        .map(|(_, l)| l)
        .collect();
    match hits.as_slice() {
        [one] => Some(*one),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn opts() -> Vec<String> {
        ["the plate", "the black bowl", "the basket", "the stove"].iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn follows_vlmevalkit() {
        let cases = [
            ("B", Extracted::Letter('B')),
            ("(C)", Extracted::Letter('C')),
            ("The answer is D.", Extracted::Letter('D')),
            ("**A**: the plate", Extracted::Letter('A')),
            ("A or B", Extracted::Unparsed),
            // "A" as an article counts as a letter token, exactly as in VLMEvalKit.
            ("A bowl is shown, so C", Extracted::Unparsed),
            ("It is the black bowl.", Extracted::Letter('B')),
            ("the plate or the stove", Extracted::Unparsed),
            ("Z", Extracted::Refused),
            ("Cannot determine the answer from this view", Extracted::Refused),
            ("<think>maybe A, maybe B</think>\nC", Extracted::Letter('C')),
            ("<think>A is likely but I ran out of tok", Extracted::Unparsed),
            ("", Extracted::Unparsed),
            ("E", Extracted::Unparsed),
            ("Failed to obtain answer via API. A", Extracted::Unparsed),
            ("b", Extracted::Unparsed),
        ];
        for (raw, expected) in cases {
            assert_eq!(extract(raw, &opts()), expected, "{raw:?}");
        }
    }
}
