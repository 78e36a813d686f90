//! The human's text as words: lower case, commas remembered, the punctuation of a sentence and
//! what shows nothing left out.
//!
//! Owns: where a word starts and ends. Must not: drop a character that could be part of a word
//! (a sign, a mark inside "1.5"), or know what any word means.

use crate::engine::scene::invisible;

/// One word of the text, lower case, whether a comma followed it, and whether a sentence ended
/// after it (".", "!", "?", ";").
#[derive(Clone, Debug)]
pub(super) struct Token {
    pub(super) word: String,
    pub(super) comma: bool,
    pub(super) end: bool,
}

/// Marks that end a sentence.
const ENDS: &str = ".!?;。！？；";

/// Words, lower case; commas remembered (a vocative or a narrowing is set off by one). The
/// punctuation of a sentence is dropped where it stands at a word's edge, and invisible
/// characters (zero-width, direction controls) wherever they are; a mark inside a word is part
/// of it ("1.5", "dr.pepper", "c.1"), as is any other character (a sign, a symbol, an emoji):
/// "the ★ vase" has a word nobody knows, which must narrow the reference to nothing.
pub(super) fn tokens(text: &str) -> Vec<Token> {
    let mut out: Vec<Token> = Vec::new();
    let comma_after_last = |out: &mut Vec<Token>| {
        if let Some(last) = out.last_mut() {
            last.comma = true;
        }
    };
    let mut chars: Vec<char> = Vec::new();
    for piece in text.split_whitespace() {
        chars.clear();
        chars.extend(piece.chars().filter(|&c| !invisible(c)));
        let mark = |c: char| c == ',' || is_punctuation(c);
        let (Some(first), Some(last)) = (
            chars.iter().position(|&c| !mark(c)),
            chars.iter().rposition(|&c| !mark(c)),
        ) else {
            if chars.contains(&',') {
                comma_after_last(&mut out);
            }
            continue;
        };
        if chars[..first].contains(&',') {
            comma_after_last(&mut out);
        }
        let mut word = String::new();
        for i in first..=last {
            match chars[i] {
                // A comma between digits is a decimal mark ("1,5"); elsewhere it sets words off.
                ',' if !(chars[i - 1].is_ascii_digit() && chars[i + 1].is_ascii_digit()) => {
                    if word.is_empty() {
                        comma_after_last(&mut out);
                    } else {
                        out.push(Token {
                            word: std::mem::take(&mut word),
                            comma: true,
                            end: false,
                        });
                    }
                }
                // "the mug.Get the vase": a full stop between a word and a capital is the end of
                // a sentence, not a mark inside a word ("1.5", "dr.pepper" stay whole).
                '.' | '!' | '?' if chars[i - 1].is_lowercase() && chars[i + 1].is_uppercase() => {
                    out.push(Token {
                        word: std::mem::take(&mut word),
                        comma: false,
                        end: true,
                    });
                }
                // Most words are ASCII: lowered without `to_lowercase`'s iterator.
                c if c.is_ascii_alphanumeric() => word.push(c.to_ascii_lowercase()),
                '\'' | '’' => word.push('\''),
                c => word.extend(c.to_lowercase()),
            }
        }
        if !word.is_empty() {
            out.push(Token {
                word,
                comma: chars[last + 1..].contains(&','),
                end: chars[last + 1..].iter().any(|&c| ENDS.contains(c)),
            });
        }
    }
    out
}

/// Marks that end or set off a sentence or a quotation, which carry no word: ASCII's and the
/// common ones of other scripts.
const PUNCTUATION: &str = ".!?;:\"`()[]{}‘“”„«»‹›…¡¿–—。、，！？：；（）「」『』";

fn is_punctuation(c: char) -> bool {
    PUNCTUATION.contains(c)
}

/// Splits tokens into sentences: each ends where a sentence's mark stands, the last at the end.
pub(super) fn sentences(tokens: Vec<Token>) -> Vec<Vec<Token>> {
    let mut out: Vec<Vec<Token>> = vec![Vec::new()];
    for token in tokens {
        let end = token.end;
        out.last_mut().expect("never empty").push(token);
        if end {
            out.push(Vec::new());
        }
    }
    out.retain(|s| !s.is_empty());
    out
}
