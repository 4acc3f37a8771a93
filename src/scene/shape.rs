//! Reading a TOML file into its serde form with every problem of its shape
//! reported at once: each unknown field, each value of the wrong type and
//! each missing field, with its path and line.
//!
//! serde stops at the first problem. Here the file is read again after each
//! one, with the problem taken out: an unknown field removed, a mistyped
//! value or a missing field replaced by a placeholder of a type the field
//! takes (tried in turn). The placeholders' values are never used: a file
//! that needed one is not returned. Values are not checked here (that is
//! the validator's job, [`super::validate`]), nor TOML syntax (its first
//! error ends the reading).

use std::ops::Range;

use serde::de::DeserializeOwned;
use toml::Spanned;
use toml::de::{DeArray, DeInteger, DeTable, DeValue, Deserializer};

use super::{FieldError, SceneError};

/// At most this many problems are taken out of one file before the
/// reading gives up (a file that is not a scene at all).
const MAX_PROBLEMS: usize = 200;

/// A file read with every problem of its shape.
pub(super) struct Read<T> {
    /// The file, if its only problems were unknown fields (removed): its
    /// values can then still be validated.
    pub(super) value: Option<T>,
    /// Every problem found, in the order of the file's lines.
    pub(super) errors: Vec<FieldError>,
}

/// Reads `text` as a `T`, collecting every unknown, mistyped or missing
/// field; `required(path)` says what a missing field at `path` needs
/// (`None`: "it is required here"). `Err` only for TOML that does not parse.
pub(super) fn read<T: DeserializeOwned>(
    text: &str,
    required: fn(&str) -> Option<&'static str>,
) -> Result<Read<T>, SceneError> {
    let mut root = DeTable::parse(text).map_err(SceneError::from_toml)?;
    let mut problems = Problems {
        text,
        required,
        errors: Vec::new(),
        placeholders: 0,
        only_unknown: true,
    };
    for _ in 0..MAX_PROBLEMS {
        let e = match T::deserialize(Deserializer::from(root.clone())) {
            Ok(value) => {
                let value = problems.only_unknown.then_some(value);
                return Ok(Read {
                    value,
                    errors: problems.sorted(),
                });
            }
            Err(e) => e,
        };
        let message = e.message().trim().to_owned();
        let span = e.span();
        if !span
            .clone()
            .is_some_and(|s| problems.take_out(&mut root, &s, &message))
        {
            // Not one we can take out: reported as it stands, and the end.
            problems.errors.push(FieldError {
                path: span
                    .as_ref()
                    .and_then(|s| path_at(&root, s))
                    .unwrap_or_default(),
                message,
                location: span.and_then(|s| line_column(text, s.start)),
            });
            break;
        }
    }
    Ok(Read {
        value: None,
        errors: problems.sorted(),
    })
}

/// The problems found so far in one file.
struct Problems<'t> {
    text: &'t str,
    /// What a missing field needs, by path.
    required: fn(&str) -> Option<&'static str>,
    errors: Vec<FieldError>,
    /// Placeholders put in: the n-th has [`placeholder_span`]`(n)`.
    placeholders: usize,
    /// Whether every problem so far was an unknown field.
    only_unknown: bool,
}

impl Problems<'_> {
    /// Takes the problem `message` at `span` out of `root`, recording it;
    /// `false` if it cannot be (the reading stops there).
    fn take_out(
        &mut self,
        root: &mut Spanned<DeTable<'_>>,
        span: &Range<usize>,
        message: &str,
    ) -> bool {
        // A placeholder of ours (or one of its elements) that does not fit:
        // the next type; a placeholder table that lacks a field: one more
        // placeholder in it, reported by nobody.
        if let Some(span) = (0..self.placeholders)
            .map(placeholder_span)
            .find(|p| p == span || *span == (p.start..p.start))
        {
            if let Some(key) = quoted(message, "missing field `") {
                let inner = candidate(0, placeholder_span(self.placeholders));
                self.placeholders += 1;
                let Some(table) = table_mut(root, &span) else {
                    return false;
                };
                table.insert(Spanned::new(inner.span(), key.to_owned().into()), inner);
                return true;
            }
            let Some(next) = next_candidate(root, &span) else {
                return false;
            };
            return value_mut(root, &span).map(|v| *v = next).is_some();
        }
        let Some(path) = path_at(root, span) else {
            return false;
        };
        // A field missing at the top has no line of its own.
        let location = (!path.is_empty() || root.span() != *span)
            .then(|| line_column(self.text, span.start))
            .flatten();
        if let Some(key) = quoted(message, "unknown field `") {
            self.errors.push(FieldError {
                path,
                message: message.replacen(&format!(" `{key}`"), "", 1),
                location,
            });
            return remove_key(root.get_mut(), span);
        }
        self.only_unknown = false;
        let placeholder = candidate(0, placeholder_span(self.placeholders));
        self.placeholders += 1;
        if let Some(key) = quoted(message, "missing field `") {
            let path = join(&path, key);
            let need = (self.required)(&path).unwrap_or("it is required here");
            self.errors.push(FieldError {
                message: format!("missing field: {need}"),
                path,
                location,
            });
            let Some(table) = table_mut(root, span) else {
                return false;
            };
            let key_span = placeholder.span();
            table.insert(Spanned::new(key_span, key.to_owned().into()), placeholder);
            return true;
        }
        self.errors.push(FieldError {
            path,
            message: message.to_owned(),
            location,
        });
        match value_mut(root, span) {
            Some(v) => {
                *v = placeholder;
                true
            }
            None => false,
        }
    }

    /// The errors in the order of the file (those without a line last), each once.
    fn sorted(mut self) -> Vec<FieldError> {
        self.errors
            .sort_by_key(|e| e.location.unwrap_or((usize::MAX, usize::MAX)));
        self.errors.dedup();
        self.errors
    }
}

/// The text between `prefix` and the next backquote of `message`.
fn quoted<'a>(message: &'a str, prefix: &str) -> Option<&'a str> {
    message.strip_prefix(prefix)?.split('`').next()
}

/// `parent.key`, or `key` at the top.
fn join(parent: &str, key: &str) -> String {
    if parent.is_empty() {
        key.to_owned()
    } else {
        format!("{parent}.{key}")
    }
}

/// The `n`-th placeholder's span: beyond any text (its elements, if it is
/// an array: the empty span at its start).
fn placeholder_span(n: usize) -> Range<usize> {
    let end = usize::MAX - 2 * n;
    end - 1..end
}

/// The number of placeholder types, in the order they are tried: an
/// integer (which serde takes for a float too), a string, a boolean, a pair
/// of numbers (a point), an empty array, an empty table.
const CANDIDATES: usize = 6;

/// The placeholder of type `kind` (see [`CANDIDATES`]) at `span`.
fn candidate<'i>(kind: usize, span: Range<usize>) -> Spanned<DeValue<'i>> {
    let zero = || {
        Spanned::new(
            span.start..span.start,
            DeValue::Integer(DeInteger::default()),
        )
    };
    let value = match kind {
        0 => DeValue::Integer(DeInteger::default()),
        1 => DeValue::String(String::new().into()),
        2 => DeValue::Boolean(false),
        3 => {
            let mut pair = DeArray::new();
            pair.push(zero());
            pair.push(zero());
            DeValue::Array(pair)
        }
        4 => DeValue::Array(DeArray::new()),
        _ => DeValue::Table(DeTable::new()),
    };
    Spanned::new(span, value)
}

/// The placeholder after the one at `span`, if there is one.
fn next_candidate<'i>(
    root: &mut Spanned<DeTable<'i>>,
    span: &Range<usize>,
) -> Option<Spanned<DeValue<'i>>> {
    let kind = match value_mut(root, span)?.get_ref() {
        DeValue::Integer(_) => 0,
        DeValue::String(_) => 1,
        DeValue::Boolean(_) => 2,
        DeValue::Array(a) if !a.is_empty() => 3,
        DeValue::Array(_) => 4,
        _ => return None,
    };
    (kind + 1 < CANDIDATES).then(|| candidate(kind + 1, span.clone()))
}

/// The path (`sprockets[1].teeth`) of the key or value at `span` (the
/// empty path: the whole file).
fn path_at(root: &Spanned<DeTable<'_>>, span: &Range<usize>) -> Option<String> {
    if root.span() == *span {
        return Some(String::new());
    }
    path_in(root.get_ref(), span, "")
}

fn path_in(table: &DeTable<'_>, span: &Range<usize>, prefix: &str) -> Option<String> {
    table.iter().find_map(|(key, value)| {
        let path = join(prefix, key.get_ref());
        if key.span() == *span {
            Some(path)
        } else {
            value_path(value, span, &path)
        }
    })
}

fn value_path(value: &Spanned<DeValue<'_>>, span: &Range<usize>, path: &str) -> Option<String> {
    let inside = match value.get_ref() {
        DeValue::Table(t) => path_in(t, span, path),
        DeValue::Array(a) => a
            .iter()
            .enumerate()
            .find_map(|(i, e)| value_path(e, span, &format!("{path}[{i}]"))),
        _ => None,
    };
    inside.or_else(|| (value.span() == *span).then(|| path.to_owned()))
}

/// The value at `span`, wherever it is; the innermost where an array of
/// tables and its first table share their span.
fn value_mut<'a, 'i>(
    root: &'a mut Spanned<DeTable<'i>>,
    span: &Range<usize>,
) -> Option<&'a mut Spanned<DeValue<'i>>> {
    in_table(root.get_mut(), span)
}

fn in_table<'a, 'i>(
    table: &'a mut DeTable<'i>,
    span: &Range<usize>,
) -> Option<&'a mut Spanned<DeValue<'i>>> {
    table.iter_mut().find_map(|(_, v)| in_value(v, span))
}

fn in_value<'a, 'i>(
    value: &'a mut Spanned<DeValue<'i>>,
    span: &Range<usize>,
) -> Option<&'a mut Spanned<DeValue<'i>>> {
    if holds(value.get_ref(), span) {
        match value.get_mut() {
            DeValue::Table(t) => in_table(t, span),
            DeValue::Array(a) => a.iter_mut().find_map(|e| in_value(e, span)),
            _ => None,
        }
    } else {
        (value.span() == *span).then_some(value)
    }
}

/// Whether a value inside `value` has `span`.
fn holds(value: &DeValue<'_>, span: &Range<usize>) -> bool {
    let at = |v: &Spanned<DeValue<'_>>| v.span() == *span || holds(v.get_ref(), span);
    match value {
        DeValue::Table(t) => t.iter().any(|(_, v)| at(v)),
        DeValue::Array(a) => a.iter().any(at),
        _ => false,
    }
}

/// The table at `span` (the root's span: the root).
fn table_mut<'a, 'i>(
    root: &'a mut Spanned<DeTable<'i>>,
    span: &Range<usize>,
) -> Option<&'a mut DeTable<'i>> {
    if root.span() == *span {
        return Some(root.get_mut());
    }
    match value_mut(root, span)?.get_mut() {
        DeValue::Table(t) => Some(t),
        _ => None,
    }
}

/// Removes the key at `span`, wherever it is.
fn remove_key(table: &mut DeTable<'_>, span: &Range<usize>) -> bool {
    if let Some(key) = table.keys().find(|k| k.span() == *span).cloned() {
        return table.remove(&key).is_some();
    }
    table.iter_mut().any(|(_, v)| match v.get_mut() {
        DeValue::Table(t) => remove_key(t, span),
        DeValue::Array(a) => a.iter_mut().any(|e| match e.get_mut() {
            DeValue::Table(t) => remove_key(t, span),
            _ => false,
        }),
        _ => false,
    })
}

/// 1-based (line, column) of byte `at` in `text`; `None` past its end.
pub(super) fn line_column(text: &str, at: usize) -> Option<(usize, usize)> {
    let before = text.get(..at)?;
    let line = before.matches('\n').count() + 1;
    let column = before.rfind('\n').map_or(at, |n| at - n - 1) + 1;
    Some((line, column))
}
