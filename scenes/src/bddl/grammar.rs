//! Recursive-descent reading of LIBERO's BDDL grammar into positioned raw parts.
//!
//! ```text
//! (define (problem CLASS)
//!   (:domain robosuite)
//!   (:language word ...)
//!   (:regions (NAME (:target T) (:ranges ((x0 y0 x1 y1) ...)) (:yaw_rotation ((a b))) (:rgba (r g b a))) ...)
//!   (:fixtures name ... - category ...)
//!   (:objects name ... - category ...)
//!   (:obj_of_interest name ...)
//!   (:init (Pred arg ...) ...)
//!   (:goal (And (Pred arg ...) ...)))          ; or a single atom without And
//! ```
//!
//! Reading the structure as it goes (rather than building a tree first) lets an error say what
//! was expected at the exact token where the file goes wrong. Names are checked later, in
//! `resolve`, once all sections are known.

use super::BddlError;
use super::lexer::{Pos, Tok, Token, tokenize};

/// A word and where it starts.
#[derive(Clone, Copy, Debug)]
pub struct Word<'a> {
    pub text: &'a str,
    pub pos: Pos,
}

impl Word<'_> {
    /// Identifiers are case-insensitive: LIBERO lower-cases the whole file.
    pub fn ident(&self) -> String {
        self.text.to_lowercase()
    }
}

#[derive(Debug)]
pub struct RawAtom<'a> {
    pub open: Pos,
    pub predicate: Word<'a>,
    pub args: Vec<Word<'a>>,
}

impl RawAtom<'_> {
    /// The atom as written, for messages.
    pub fn text(&self) -> String {
        let mut s = format!("({}", self.predicate.text);
        for arg in &self.args {
            s.push(' ');
            s.push_str(arg.text);
        }
        s.push(')');
        s
    }
}

#[derive(Debug)]
pub struct RawEntity<'a> {
    pub name: Word<'a>,
    pub category: Word<'a>,
}

#[derive(Debug)]
pub struct RawRegion<'a> {
    pub name: Word<'a>,
    pub target: Word<'a>,
    pub ranges: Vec<[f64; 4]>,
    pub yaw_rotation: Option<[f64; 2]>,
    pub rgba: Option<[f64; 4]>,
}

#[derive(Debug)]
pub struct RawProblem<'a> {
    pub problem: Word<'a>,
    pub language: String,
    pub regions: Vec<RawRegion<'a>>,
    pub fixtures: Vec<RawEntity<'a>>,
    pub objects: Vec<RawEntity<'a>>,
    pub obj_of_interest: Vec<Word<'a>>,
    pub init: Vec<RawAtom<'a>>,
    pub goal: Vec<RawAtom<'a>>,
}

/// Section names, for the "expected" part of messages.
const SECTIONS: &str = "problem, :domain, :language, :regions, :fixtures, :objects, :obj_of_interest, :init or :goal";

/// Reads a whole BDDL problem.
pub fn read<'a>(text: &'a str, file: &'a str) -> Result<RawProblem<'a>, BddlError> {
    let mut p = Parser { tokens: tokenize(text), at: 0, file };
    p.open("'(' starting (define ...)")?;
    let define = p.word("'define'")?;
    if !define.text.eq_ignore_ascii_case("define") {
        return p.fail_at(define.pos, "'define'", format!("'{}'", define.text));
    }
    let mut sections = Sections::default();
    loop {
        match p.peek().tok {
            Tok::Close => break,
            Tok::Open => p.section(&mut sections)?,
            _ => return p.fail("'(' starting a section or ')' closing (define"),
        }
    }
    let close = p.bump();
    if p.peek().tok != Tok::End {
        return p.fail("end of file after the ')' closing (define");
    }
    let missing = |what: &str| p.fail_at::<RawProblem>(close.pos, what, "')' closing (define".to_string());
    let Some(problem) = sections.problem else {
        return missing("a (problem NAME) section");
    };
    let Some(goal) = sections.goal else {
        return missing("a (:goal ...) section");
    };
    Ok(RawProblem {
        problem,
        language: sections.language.unwrap_or_default(),
        regions: sections.regions.unwrap_or_default(),
        fixtures: sections.fixtures.unwrap_or_default(),
        objects: sections.objects.unwrap_or_default(),
        obj_of_interest: sections.obj_of_interest.unwrap_or_default(),
        init: sections.init.unwrap_or_default(),
        goal,
    })
}

/// Sections read so far; `seen` keeps each head and where it was, to report repeats.
#[derive(Default)]
struct Sections<'a> {
    seen: Vec<(String, Pos)>,
    problem: Option<Word<'a>>,
    language: Option<String>,
    regions: Option<Vec<RawRegion<'a>>>,
    fixtures: Option<Vec<RawEntity<'a>>>,
    objects: Option<Vec<RawEntity<'a>>>,
    obj_of_interest: Option<Vec<Word<'a>>>,
    init: Option<Vec<RawAtom<'a>>>,
    goal: Option<Vec<RawAtom<'a>>>,
}

struct Parser<'a> {
    tokens: Vec<Token<'a>>,
    at: usize,
    file: &'a str,
}

impl<'a> Parser<'a> {
    fn peek(&self) -> Token<'a> {
        self.tokens[self.at]
    }

    /// Consumes the next token (the final `End` is never consumed).
    fn bump(&mut self) -> Token<'a> {
        let token = self.peek();
        if token.tok != Tok::End {
            self.at += 1;
        }
        token
    }

    fn fail_at<T>(&self, pos: Pos, expected: &str, found: String) -> Result<T, BddlError> {
        Err(BddlError {
            file: self.file.to_string(),
            line: pos.line,
            column: pos.column,
            expected: expected.to_string(),
            found,
        })
    }

    /// Fails at the next token.
    fn fail<T>(&self, expected: &str) -> Result<T, BddlError> {
        let token = self.peek();
        self.fail_at(token.pos, expected, token.tok.describe())
    }

    fn open(&mut self, expected: &str) -> Result<Pos, BddlError> {
        match self.peek().tok {
            Tok::Open => Ok(self.bump().pos),
            _ => self.fail(expected),
        }
    }

    /// Consumes the `)` that closes `what` (e.g. `(:objects`).
    fn close(&mut self, what: &str) -> Result<(), BddlError> {
        match self.peek().tok {
            Tok::Close => {
                self.bump();
                Ok(())
            }
            _ => self.fail(&format!("')' closing {what}")),
        }
    }

    fn word(&mut self, expected: &str) -> Result<Word<'a>, BddlError> {
        match self.peek().tok {
            Tok::Word(text) => Ok(Word { text, pos: self.bump().pos }),
            _ => self.fail(expected),
        }
    }

    /// Words up to the `)` closing `what`.
    fn words_until_close(&mut self, what: &str) -> Result<Vec<Word<'a>>, BddlError> {
        let mut words = Vec::new();
        loop {
            match self.peek().tok {
                Tok::Close => {
                    self.bump();
                    return Ok(words);
                }
                Tok::Word(text) => words.push(Word { text, pos: self.bump().pos }),
                _ => return self.fail(&format!("a word or ')' closing {what}")),
            }
        }
    }

    /// A finite number, read as LIBERO's `float()` would.
    fn number(&mut self, what: &str) -> Result<f64, BddlError> {
        let word = self.word(&format!("a number ({what})"))?;
        match word.text.parse::<f64>() {
            Ok(value) if value.is_finite() => Ok(value),
            _ => self.fail_at(word.pos, &format!("a finite number ({what})"), format!("'{}'", word.text)),
        }
    }

    fn numbers<const N: usize>(&mut self, what: &str) -> Result<[f64; N], BddlError> {
        let mut values = [0.0; N];
        for value in &mut values {
            *value = self.number(what)?;
        }
        Ok(values)
    }

    fn section(&mut self, sections: &mut Sections<'a>) -> Result<(), BddlError> {
        self.bump(); // '('
        let head = self.word(&format!("a section name ({SECTIONS})"))?;
        let key = head.ident();
        if let Some((_, first)) = sections.seen.iter().find(|(k, _)| *k == key) {
            let expected = format!("each section once ({key} was first given at line {})", first.line);
            return self.fail_at(head.pos, &expected, format!("a second ({key}"));
        }
        sections.seen.push((key.clone(), head.pos));
        let what = format!("({key}");
        match key.as_str() {
            "problem" => {
                sections.problem = Some(self.word("a problem class name")?);
                self.close(&what)?;
            }
            ":domain" => {
                let domain = self.word("'robosuite'")?;
                if domain.ident() != "robosuite" {
                    return self.fail_at(domain.pos, "'robosuite'", format!("'{}'", domain.text));
                }
                self.close(&what)?;
            }
            ":language" => {
                let words = self.words_until_close(&what)?;
                sections.language = Some(words.iter().map(|w| w.text).collect::<Vec<_>>().join(" "));
            }
            ":requirements" => {
                // Accepted and ignored, as LIBERO does.
                self.words_until_close(&what)?;
            }
            ":regions" => {
                let mut regions = Vec::new();
                while self.peek().tok != Tok::Close {
                    regions.push(self.region()?);
                }
                self.bump();
                sections.regions = Some(regions);
            }
            ":fixtures" => sections.fixtures = Some(self.typed_names(&what)?),
            ":objects" => sections.objects = Some(self.typed_names(&what)?),
            ":obj_of_interest" => sections.obj_of_interest = Some(self.words_until_close(&what)?),
            ":init" => {
                let mut atoms = Vec::new();
                while self.peek().tok != Tok::Close {
                    let open = self.open("'(' starting an atom or ')' closing (:init")?;
                    let predicate = self.word("a predicate name")?;
                    atoms.push(self.atom_args(open, predicate)?);
                }
                self.bump();
                sections.init = Some(atoms);
            }
            ":goal" => {
                sections.goal = Some(self.goal()?);
                self.close(&what)?;
            }
            _ => {
                return self.fail_at(head.pos, &format!("a section name ({SECTIONS})"), format!("'{}'", head.text));
            }
        }
        Ok(())
    }

    /// The arguments of an atom whose `(` and predicate were read, up to its `)`.
    /// A `(` after the predicate is a nested group such as `(Not (On a b))`, which LIBERO's
    /// grammar has no place for: said as such rather than as a misplaced parenthesis.
    fn atom_args(&mut self, open: Pos, predicate: Word<'a>) -> Result<RawAtom<'a>, BddlError> {
        if self.peek().tok == Tok::Open {
            return self.fail_at(
                predicate.pos,
                "an atom of names: LIBERO's atoms are (Predicate name ...), joined only by one (And ...) in the goal, without Not, Or or nesting",
                format!("'({} (' opening a nested group", predicate.text),
            );
        }
        let args = self.words_until_close(&format!("({}", predicate.text))?;
        Ok(RawAtom { open, predicate, args })
    }

    /// `(And atom ...)` or a single atom.
    fn goal(&mut self) -> Result<Vec<RawAtom<'a>>, BddlError> {
        let open = self.open("'(' starting the goal, e.g. (And (On a b))")?;
        let head = self.word("'And' or a predicate name")?;
        if !head.text.eq_ignore_ascii_case("and") {
            return Ok(vec![self.atom_args(open, head)?]);
        }
        let mut atoms = Vec::new();
        loop {
            match self.peek().tok {
                Tok::Close if atoms.is_empty() => return self.fail("at least one goal atom in (And"),
                Tok::Close => {
                    self.bump();
                    return Ok(atoms);
                }
                _ => {
                    let open = self.open("'(' starting a goal atom or ')' closing (And")?;
                    let predicate = self.word("a predicate name")?;
                    atoms.push(self.atom_args(open, predicate)?);
                }
            }
        }
    }

    /// `name ... - category name ... - category`, up to the `)` closing `what`.
    fn typed_names(&mut self, what: &str) -> Result<Vec<RawEntity<'a>>, BddlError> {
        let mut entities = Vec::new();
        let mut pending: Vec<Word<'a>> = Vec::new();
        let mut categories: Vec<(String, Pos)> = Vec::new();
        loop {
            match self.peek().tok {
                Tok::Close => {
                    if let Some(first) = pending.first() {
                        let names: Vec<&str> = pending.iter().map(|w| w.text).collect();
                        let expected = format!("'- <category>' after '{}'", names.join(" "));
                        return self.fail_at(first.pos, &expected, "')'".to_string());
                    }
                    self.bump();
                    return Ok(entities);
                }
                Tok::Word("-") => {
                    let dash = self.bump();
                    if pending.is_empty() {
                        return self.fail_at(dash.pos, "a name before '-'", "'-'".to_string());
                    }
                    let category = self.word("a category after '-'")?;
                    let key = category.ident();
                    if let Some((_, first)) = categories.iter().find(|(c, _)| *c == key) {
                        // LIBERO keys these lists by category, so a second group would silently
                        // replace the first.
                        let expected = format!(
                            "all '{key}' names in one group (the category was given at line {})",
                            first.line
                        );
                        return self.fail_at(category.pos, &expected, format!("a second '- {}'", category.text));
                    }
                    categories.push((key, category.pos));
                    entities.extend(pending.drain(..).map(|name| RawEntity { name, category }));
                }
                Tok::Word(text) => pending.push(Word { text, pos: self.bump().pos }),
                _ => return self.fail(&format!("a name, '-' or ')' closing {what}")),
            }
        }
    }

    fn region(&mut self) -> Result<RawRegion<'a>, BddlError> {
        self.open("'(' starting a region or ')' closing (:regions")?;
        let name = self.word("a region name")?;
        let what = format!("({}", name.text);
        let mut target = None;
        let mut ranges = None;
        let mut yaw_rotation = None;
        let mut rgba = None;
        loop {
            if self.peek().tok == Tok::Close {
                break;
            }
            self.open(&format!("'(' starting a region attribute or ')' closing {what}"))?;
            let attribute = self.word("a region attribute (:target, :ranges, :yaw_rotation or :rgba)")?;
            let key = attribute.ident();
            let seen = match key.as_str() {
                ":target" => target.is_some(),
                ":ranges" => ranges.is_some(),
                ":yaw_rotation" => yaw_rotation.is_some(),
                ":rgba" => rgba.is_some(),
                _ => false,
            };
            if seen {
                return self.fail_at(attribute.pos, &format!("each attribute once in {what}"), format!("a second ({key}"));
            }
            match key.as_str() {
                ":target" => target = Some(self.word("the target's name")?),
                ":ranges" => ranges = Some(self.ranges()?),
                ":yaw_rotation" => {
                    self.open("'(' starting the list of yaw ranges")?;
                    self.open("'(' starting a yaw range (min max)")?;
                    yaw_rotation = Some(self.numbers::<2>("yaw min, max")?);
                    self.close("the yaw range after 2 numbers (one range per region)")?;
                    self.close("the list of yaw ranges (one range per region)")?;
                }
                ":rgba" => {
                    self.open("'(' starting the colour (r g b a)")?;
                    rgba = Some(self.numbers::<4>("r, g, b, a")?);
                    self.close("the colour after 4 numbers")?;
                }
                _ => {
                    return self.fail_at(
                        attribute.pos,
                        "a region attribute (:target, :ranges, :yaw_rotation or :rgba)",
                        format!("'{}'", attribute.text),
                    );
                }
            }
            self.close(&format!("({key}"))?;
        }
        let Some(target) = target else {
            return self.fail(&format!("a (:target NAME) attribute in {what}"));
        };
        self.bump();
        Ok(RawRegion { name, target, ranges: ranges.unwrap_or_default(), yaw_rotation, rgba })
    }

    /// `((x_min y_min x_max y_max) ...)`, at least one rectangle, each with min <= max.
    fn ranges(&mut self) -> Result<Vec<[f64; 4]>, BddlError> {
        self.open("'(' starting the list of ranges")?;
        let mut ranges = Vec::new();
        loop {
            match self.peek().tok {
                Tok::Close if ranges.is_empty() => return self.fail("'(' starting a range (x_min y_min x_max y_max)"),
                Tok::Close => {
                    self.bump();
                    return Ok(ranges);
                }
                _ => {
                    let open = self.open("'(' starting a range (x_min y_min x_max y_max) or ')' closing the list")?;
                    let range = self.numbers::<4>("x_min, y_min, x_max, y_max")?;
                    self.close("the range after 4 numbers")?;
                    let [x0, y0, x1, y1] = range;
                    if x1 < x0 || y1 < y0 {
                        // LIBERO asserts this when it turns a range into a site.
                        return self.fail_at(
                            open,
                            "a range with x_min <= x_max and y_min <= y_max",
                            format!("({x0} {y0} {x1} {y1})"),
                        );
                    }
                    ranges.push(range);
                }
            }
        }
    }
}
