//! The value of a run attribute ([`super::RunResults::attributes`]): text,
//! a number or a flag, so that the results file stores numbers as HDF5
//! numbers (`speed_m_s = 22.0` as a 64-bit float, `steps = 50910` as a
//! 64-bit integer) and a reader gets them without parsing.
//!
//! Files written before the values were typed hold every attribute as a
//! string: those are read back as [`AttrValue::Text`] unchanged (nothing is
//! guessed), and the numeric accessors ([`AttrValue::as_f64`],
//! [`AttrValue::as_i64`]) parse such a text when it is a number, so code
//! reading `steps` or `speed_m_s` works on old and new files alike
//! (docs/reference/04-table-files.md §4.4, "Root attributes").

use std::fmt;

/// A run attribute's value.
#[derive(Debug, Clone, PartialEq)]
pub enum AttrValue {
    /// A string (HDF5 variable-length UTF-8).
    Text(String),
    /// A real number (HDF5 f64); its unit is in the attribute's name.
    Float(f64),
    /// A count or an integer setting (HDF5 i64).
    Int(i64),
    /// A flag (HDF5 u8 holding 0 or 1; HDF5 has no boolean type).
    Bool(bool),
}

impl AttrValue {
    /// The text, when the value is [`AttrValue::Text`].
    pub fn as_str(&self) -> Option<&str> {
        match self {
            AttrValue::Text(s) => Some(s),
            _ => None,
        }
    }

    /// The value as a real number: a float, an integer, or a text that
    /// parses as one (files from before the values were typed).
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            AttrValue::Float(v) => Some(*v),
            AttrValue::Int(v) => Some(*v as f64),
            AttrValue::Text(s) => s.trim().parse().ok(),
            AttrValue::Bool(_) => None,
        }
    }

    /// The value as an integer: an integer, or a text that parses as one.
    pub fn as_i64(&self) -> Option<i64> {
        match self {
            AttrValue::Int(v) => Some(*v),
            AttrValue::Text(s) => s.trim().parse().ok(),
            _ => None,
        }
    }

    /// The flag, when the value is [`AttrValue::Bool`].
    pub fn as_bool(&self) -> Option<bool> {
        match self {
            AttrValue::Bool(b) => Some(*b),
            _ => None,
        }
    }
}

/// As a user reads it: the text, or the number in Rust's shortest
/// round-trip form (`22`, `0.001`, `50910`), or `true`/`false`.
impl fmt::Display for AttrValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            AttrValue::Text(s) => f.write_str(s),
            AttrValue::Float(v) => write!(f, "{v}"),
            AttrValue::Int(v) => write!(f, "{v}"),
            AttrValue::Bool(b) => write!(f, "{b}"),
        }
    }
}

impl From<String> for AttrValue {
    fn from(s: String) -> Self {
        AttrValue::Text(s)
    }
}

impl From<&str> for AttrValue {
    fn from(s: &str) -> Self {
        AttrValue::Text(s.to_string())
    }
}

impl From<f64> for AttrValue {
    fn from(v: f64) -> Self {
        AttrValue::Float(v)
    }
}

impl From<i64> for AttrValue {
    fn from(v: i64) -> Self {
        AttrValue::Int(v)
    }
}

/// Counts above `i64::MAX` (never reached by a run) saturate.
impl From<u64> for AttrValue {
    fn from(v: u64) -> Self {
        AttrValue::Int(i64::try_from(v).unwrap_or(i64::MAX))
    }
}

impl From<usize> for AttrValue {
    fn from(v: usize) -> Self {
        AttrValue::Int(i64::try_from(v).unwrap_or(i64::MAX))
    }
}

impl From<bool> for AttrValue {
    fn from(b: bool) -> Self {
        AttrValue::Bool(b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_from_typed_values_and_from_old_texts() {
        assert_eq!(AttrValue::from(22.0).as_f64(), Some(22.0));
        assert_eq!(AttrValue::from(50910_u64).as_i64(), Some(50910));
        assert_eq!(AttrValue::from(50910_u64).as_f64(), Some(50910.0));
        // An old file's string attributes.
        assert_eq!(AttrValue::from("22").as_f64(), Some(22.0));
        assert_eq!(AttrValue::from("50910").as_i64(), Some(50910));
        assert_eq!(AttrValue::from("polach").as_f64(), None);
        assert_eq!(AttrValue::from(true).as_bool(), Some(true));
        assert_eq!(AttrValue::from(1.5).as_i64(), None);
        assert_eq!(AttrValue::from(22.0).to_string(), "22");
        assert_eq!(AttrValue::from(1e-3).to_string(), "0.001");
        assert_eq!(AttrValue::from("completed").as_str(), Some("completed"));
        assert_eq!(AttrValue::from(0_i64).as_str(), None);
    }
}
