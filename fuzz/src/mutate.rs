//! Mutations of scene text, chosen by a seeded generator (so a campaign is
//! reproducible from its seed): token edits that keep most of the file
//! meaningful, so that the checks deep inside are reached, and byte edits
//! that do not.

use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;

/// Numbers that break naive code: non-finite, huge, tiny, negative zero,
/// integers at and past the edges of u32, u64 and i64.
const SPECIAL_NUMBERS: &[&str] = &[
    "NaN",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "3e38",
    "-3e38",
    "1e39",
    "1e-45",
    "1e-300",
    "-0",
    "-0.0",
    "0",
    "-1",
    "1e9",
    "-1e9",
    "4294967295",
    "4294967296",
    "9223372036854775807",
    "-9223372036854775808",
    "18446744073709551615",
    "18446744073709551616",
    "99999999999999999999999999999",
    "0.000000000000000000000000000000000000000001",
];

/// A piece of scene text, as the mutations see it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Number,
    Identifier,
    Text,
    Punctuation,
    Space,
}

#[derive(Clone, Debug)]
struct Token {
    kind: Kind,
    text: String,
}

/// Splits RON text into tokens; concatenating them gives the text back.
fn tokens(text: &str) -> Vec<Token> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let start = i;
        let kind = if c.is_whitespace() {
            while i < chars.len() && chars[i].is_whitespace() {
                i += 1;
            }
            Kind::Space
        } else if c == '/' && chars.get(i + 1) == Some(&'/') {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
            Kind::Space
        } else if c == '"' {
            i += 1;
            while i < chars.len() && chars[i] != '"' {
                i += if chars[i] == '\\' { 2 } else { 1 };
            }
            i = (i + 1).min(chars.len());
            Kind::Text
        } else if c.is_ascii_digit() || ((c == '-' || c == '+') && chars.get(i + 1).is_some_and(char::is_ascii_digit)) {
            i += 1;
            while i < chars.len()
                && (chars[i].is_ascii_alphanumeric()
                    || chars[i] == '.'
                    || ((chars[i] == '-' || chars[i] == '+') && matches!(chars[i - 1], 'e' | 'E')))
            {
                i += 1;
            }
            Kind::Number
        } else if c.is_alphabetic() || c == '_' {
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            Kind::Identifier
        } else {
            i += 1;
            Kind::Punctuation
        };
        out.push(Token {
            kind,
            text: chars[start..i].iter().collect(),
        });
    }
    out
}

/// Makes mutated scenes from seed scenes.
#[derive(Debug)]
pub struct Mutator {
    rng: Pcg64,
}

impl Mutator {
    /// A mutator whose choices follow `seed`.
    #[must_use]
    pub fn new(seed: u64) -> Self {
        Self {
            rng: Pcg64::seed_from_u64(seed),
        }
    }

    /// One to four mutations of one of `seeds`, sometimes spliced with another.
    #[must_use]
    pub fn mutate(&mut self, seeds: &[String]) -> String {
        if seeds.is_empty() {
            return String::new();
        }
        let base = &seeds[self.rng.random_range(0..seeds.len())];
        let mut text = base.clone();
        for _ in 0..self.rng.random_range(1..=4) {
            let donor = &seeds[self.rng.random_range(0..seeds.len())];
            text = self.mutate_once(&text, donor);
        }
        text
    }

    fn pick(&mut self, tokens: &[Token], kind: Kind) -> Option<usize> {
        let matching: Vec<usize> = (0..tokens.len()).filter(|&k| tokens[k].kind == kind).collect();
        (!matching.is_empty()).then(|| matching[self.rng.random_range(0..matching.len())])
    }

    fn mutate_once(&mut self, text: &str, donor: &str) -> String {
        let mut t = tokens(text);
        if t.is_empty() {
            return "(".repeat(self.rng.random_range(1..100));
        }
        match self.rng.random_range(0..12) {
            // A number replaced by a special one (the most fruitful edit).
            0..=2 => {
                if let Some(k) = self.pick(&t, Kind::Number) {
                    t[k].text = SPECIAL_NUMBERS[self.rng.random_range(0..SPECIAL_NUMBERS.len())].into();
                }
            }
            // A number scaled far out, or made an arbitrary integer.
            3 => {
                if let Some(k) = self.pick(&t, Kind::Number) {
                    t[k].text = if self.rng.random::<bool>() {
                        format!(
                            "{}e{}",
                            t[k].text.trim_start_matches('+'),
                            self.rng.random_range(-60..60)
                        )
                    } else {
                        self.rng.random::<u64>().to_string()
                    };
                }
            }
            // A misspelt field or variant name.
            4 => {
                if let Some(k) = self.pick(&t, Kind::Identifier) {
                    let mut chars: Vec<char> = t[k].text.chars().collect();
                    let at = self.rng.random_range(0..chars.len());
                    match self.rng.random_range(0..3) {
                        0 if chars.len() > 1 => {
                            chars.remove(at);
                        }
                        1 => chars.insert(at, 'x'),
                        _ => {
                            let other = self.rng.random_range(0..chars.len());
                            chars.swap(at, other);
                        }
                    }
                    t[k].text = chars.into_iter().collect();
                }
            }
            // A field written twice: `name: value,` repeated.
            5 => {
                if let Some(k) = self.pick(&t, Kind::Identifier) {
                    let end = value_end(&t, k);
                    let copy: String = t[k..end].iter().map(|x| x.text.as_str()).collect();
                    t.insert(
                        end,
                        Token {
                            kind: Kind::Space,
                            text: format!(", {copy}"),
                        },
                    );
                }
            }
            // A token deleted or doubled.
            6 => {
                let k = self.rng.random_range(0..t.len());
                if self.rng.random::<bool>() {
                    t.remove(k);
                } else {
                    let copy = t[k].clone();
                    t.insert(k, copy);
                }
            }
            // Deep nesting, closed or not.
            7 => {
                let k = self.rng.random_range(0..t.len());
                let depth = self.rng.random_range(1..20_000);
                let (open, close) = if self.rng.random::<bool>() {
                    ("(", ")")
                } else {
                    ("[", "]")
                };
                let closing = if self.rng.random::<bool>() {
                    close.repeat(depth)
                } else {
                    String::new()
                };
                t.insert(
                    k,
                    Token {
                        kind: Kind::Punctuation,
                        text: format!("{}{closing}", open.repeat(depth)),
                    },
                );
            }
            // A long string or name.
            8 => {
                let long = "x".repeat(self.rng.random_range(1_000..200_000));
                if let Some(k) = self.pick(&t, Kind::Text) {
                    t[k].text = format!("\"{long}\"");
                } else if let Some(k) = self.pick(&t, Kind::Identifier) {
                    t[k].text = long;
                }
            }
            // A run of another scene's tokens spliced in.
            9 => {
                let d = tokens(donor);
                if !d.is_empty() {
                    let from = self.rng.random_range(0..d.len());
                    let to = (from + self.rng.random_range(1..40)).min(d.len());
                    let at = self.rng.random_range(0..t.len());
                    for (n, token) in d[from..to].iter().enumerate() {
                        t.insert(at + n, token.clone());
                    }
                }
            }
            // Bytes: one inserted, deleted or replaced (any character).
            _ => {
                let mut chars: Vec<char> = text.chars().collect();
                let at = self.rng.random_range(0..chars.len());
                let c = char::from_u32(self.rng.random_range(0..0x250)).unwrap_or('\u{fffd}');
                match self.rng.random_range(0..3) {
                    0 => chars.insert(at, c),
                    1 => {
                        chars.remove(at);
                    }
                    _ => chars[at] = c,
                }
                return chars.into_iter().collect();
            }
        }
        t.iter().map(|x| x.text.as_str()).collect()
    }
}

/// The token after the value that follows identifier `k` (`name: value`),
/// at the same bracket depth: the next `,` or unmatched closing bracket.
fn value_end(t: &[Token], k: usize) -> usize {
    let mut depth = 0i32;
    for (n, token) in t.iter().enumerate().skip(k + 1) {
        match token.text.as_str() {
            "(" | "[" | "{" => depth += 1,
            ")" | "]" | "}" if depth == 0 => return n,
            ")" | "]" | "}" => depth -= 1,
            "," if depth == 0 => return n,
            _ => {}
        }
    }
    t.len()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_give_the_text_back() {
        let text = "SceneFile(\n  // a comment\n  name: Some(\"a \\\"b\\\"\"), rate: Hz(1e-3), seed: -5,\n)";
        let joined: String = tokens(text).iter().map(|t| t.text.as_str()).collect();
        assert_eq!(joined, text);
        let numbers: Vec<String> = tokens(text)
            .into_iter()
            .filter(|t| t.kind == Kind::Number)
            .map(|t| t.text)
            .collect();
        assert_eq!(numbers, ["1e-3", "-5"]);
    }

    #[test]
    fn the_same_seed_makes_the_same_mutations() {
        let seeds = vec!["SceneFile(particles: [(position: (0, 1, 0))])".to_string()];
        let a: Vec<String> = {
            let mut m = Mutator::new(7);
            (0..50).map(|_| m.mutate(&seeds)).collect()
        };
        let mut m = Mutator::new(7);
        let b: Vec<String> = (0..50).map(|_| m.mutate(&seeds)).collect();
        assert_eq!(a, b);
        assert!(a.iter().any(|t| t != &seeds[0]), "something was mutated");
    }
}
