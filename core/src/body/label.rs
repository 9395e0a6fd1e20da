//! Short inline names for cylinders and table columns, so an error can name
//! the cylinder it is about and still be a small `Copy` value.

use core::fmt;

use serde::{Serialize, Serializer};

/// The longest name a [`Label`] holds, in bytes of UTF-8.
pub const LABEL_BYTES: usize = 16;

/// A name of at most [`LABEL_BYTES`] bytes, stored inline.
///
/// ```
/// use morphogen::body::Label;
/// assert_eq!(Label::new("left-fore-cannon").as_str(), "left-fore-cannon");
/// assert!(Label::try_new("a-much-too-long-cylinder-name").is_none());
/// ```
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Label {
    bytes: [u8; LABEL_BYTES],
    len: u8,
}

impl Label {
    /// `name`, truncated at a character boundary to [`LABEL_BYTES`] bytes
    /// (`const`, for built-in models).
    #[must_use]
    pub const fn new(name: &str) -> Label {
        let src = name.as_bytes();
        let mut len = if src.len() < LABEL_BYTES {
            src.len()
        } else {
            LABEL_BYTES
        };
        // Back off to a character boundary (a continuation byte is 10xxxxxx).
        while len > 0 && len < src.len() && (src[len] & 0xC0) == 0x80 {
            len -= 1;
        }
        let mut bytes = [0u8; LABEL_BYTES];
        let mut i = 0;
        while i < len {
            bytes[i] = src[i];
            i += 1;
        }
        Label {
            bytes,
            len: len as u8,
        }
    }

    /// `name`, or `None` when it is longer than [`LABEL_BYTES`] bytes.
    #[must_use]
    pub const fn try_new(name: &str) -> Option<Label> {
        if name.len() > LABEL_BYTES {
            None
        } else {
            Some(Label::new(name))
        }
    }

    /// The name.
    #[must_use]
    pub fn as_str(&self) -> &str {
        let used = &self.bytes[..usize::from(self.len).min(LABEL_BYTES)];
        // Built only from whole characters of a `&str`, so always UTF-8.
        core::str::from_utf8(used).unwrap_or("?")
    }
}

impl fmt::Debug for Label {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(self.as_str(), f)
    }
}

impl fmt::Display for Label {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

#[cfg(feature = "defmt")]
impl defmt::Format for Label {
    fn format(&self, f: defmt::Formatter<'_>) {
        defmt::write!(f, "{=str}", self.as_str());
    }
}

impl Serialize for Label {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.as_str())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn truncates_at_a_character_boundary() {
        assert_eq!(
            Label::new("abcdefghijklmnopqrstu").as_str(),
            "abcdefghijklmnop"
        );
        // 15 ASCII bytes then a 2-byte 'é': the 'é' would straddle byte 16.
        assert_eq!(Label::new("abcdefghijklmnoé").as_str(), "abcdefghijklmno");
        assert_eq!(Label::new("").as_str(), "");
        assert_eq!(Label::try_new("exactly-16-bytes").map(|l| l.len), Some(16));
    }
}
