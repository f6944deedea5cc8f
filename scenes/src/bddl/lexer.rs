//! Splits BDDL text into parentheses and words, each with its line and column.
//!
//! Same token rules as BDDL's `scan_tokens`: `;` starts a comment that runs to the end of the
//! line (even inside a word), and a word is a run of characters that are neither whitespace nor
//! parentheses. Unlike `scan_tokens` we do not lower-case here, so `:language` keeps its case;
//! the grammar lower-cases identifiers itself.

/// A 1-based line and column (in characters).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pos {
    pub line: usize,
    pub column: usize,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tok<'a> {
    Open,
    Close,
    Word(&'a str),
    /// Always the last token, positioned just after the text.
    End,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Token<'a> {
    pub tok: Tok<'a>,
    pub pos: Pos,
}

impl Tok<'_> {
    /// How error messages name this token.
    pub fn describe(&self) -> String {
        match self {
            Tok::Open => "'('".to_string(),
            Tok::Close => "')'".to_string(),
            Tok::Word(w) => format!("'{w}'"),
            Tok::End => "end of file".to_string(),
        }
    }
}

/// Tokenizes the whole text; the result always ends with [`Tok::End`].
pub fn tokenize(text: &str) -> Vec<Token<'_>> {
    let mut tokens = Vec::new();
    let mut pos = Pos { line: 1, column: 1 };
    let mut chars = text.char_indices().peekable();
    // Start of the word being read: byte offset and position.
    let mut word: Option<(usize, Pos)> = None;
    let mut in_comment = false;
    while let Some((offset, c)) = chars.next() {
        let ends_word = in_comment || c == ';' || c == '(' || c == ')' || c.is_whitespace();
        if ends_word && let Some((start, start_pos)) = word.take() {
            tokens.push(Token { tok: Tok::Word(&text[start..offset]), pos: start_pos });
        }
        if in_comment {
            in_comment = c != '\n';
        } else if c == ';' {
            in_comment = true;
        } else if c == '(' {
            tokens.push(Token { tok: Tok::Open, pos });
        } else if c == ')' {
            tokens.push(Token { tok: Tok::Close, pos });
        } else if !c.is_whitespace() && word.is_none() {
            word = Some((offset, pos));
        }
        if c == '\n' {
            pos = Pos { line: pos.line + 1, column: 1 };
        } else {
            pos.column += 1;
        }
        if chars.peek().is_none()
            && let Some((start, start_pos)) = word.take()
        {
            tokens.push(Token { tok: Tok::Word(&text[start..]), pos: start_pos });
        }
    }
    tokens.push(Token { tok: Tok::End, pos });
    tokens
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(text: &str) -> Vec<Tok<'_>> {
        tokenize(text).into_iter().map(|t| t.tok).collect()
    }

    #[test]
    fn words_parens_and_comments() {
        assert_eq!(
            kinds("(On a_1 b) ; trailing\n(x;y z\n)"),
            [
                Tok::Open,
                Tok::Word("On"),
                Tok::Word("a_1"),
                Tok::Word("b"),
                Tok::Close,
                Tok::Open,
                Tok::Word("x"),
                Tok::Close,
                Tok::End
            ]
        );
        assert_eq!(kinds("word"), [Tok::Word("word"), Tok::End]);
        assert_eq!(kinds(""), [Tok::End]);
    }

    #[test]
    fn positions_are_one_based_lines_and_character_columns() {
        let tokens = tokenize("(a\n  bé c)\n");
        let at: Vec<(usize, usize)> = tokens.iter().map(|t| (t.pos.line, t.pos.column)).collect();
        assert_eq!(at, [(1, 1), (1, 2), (2, 3), (2, 6), (2, 7), (3, 1)]);
    }
}
