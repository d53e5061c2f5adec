//! Image metadata: an ordered list of `key = value` text entries written into every output file
//! (PNG `tEXt`/`iTXt` chunks, EXR string attributes) and read back by
//! [`read_metadata`](super::output::read_metadata). Keys written by Penumbra itself start with
//! `penumbra.`, e.g. `penumbra.aov.depth.max`.

/// Ordered `key = value` text entries; keys are unique when built with [`Metadata::set`].
///
/// # Examples
/// ```
/// # use penumbra::film::Metadata;
/// let mut meta = Metadata::default();
/// meta.set("Software", "penumbra");
/// meta.set("Software", "penumbra 0.1");
/// assert_eq!(meta.get("Software"), Some("penumbra 0.1"));
/// assert_eq!(meta.entries.len(), 1);
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Metadata {
    /// The entries in insertion order.
    pub entries: Vec<(String, String)>,
}

impl Metadata {
    /// The value of the first entry named `key`.
    pub fn get(&self, key: &str) -> Option<&str> {
        self.entries.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
    }

    /// Sets `key` to `value`, replacing an existing entry in place or appending a new one.
    pub fn set(&mut self, key: impl Into<String>, value: impl Into<String>) {
        let (key, value) = (key.into(), value.into());
        match self.entries.iter_mut().find(|(k, _)| *k == key) {
            Some(entry) => entry.1 = value,
            None => self.entries.push((key, value)),
        }
    }

    /// A copy with `extra`'s entries set on top (replacing same-named ones).
    pub(crate) fn merged(&self, extra: &[(String, String)]) -> Metadata {
        let mut out = self.clone();
        for (k, v) in extra {
            out.set(k.clone(), v.clone());
        }
        out
    }

    /// Checks that every entry can be stored in both PNG and EXR: keys of 1–79 Latin-1
    /// characters without NUL or leading/trailing spaces (the PNG keyword rule, stricter than
    /// EXR's), values without NUL. Returns the first offending key and the reason.
    pub(crate) fn validate(&self) -> Result<(), (String, &'static str)> {
        for (key, value) in &self.entries {
            let bad = |reason| Err((key.clone(), reason));
            if key.is_empty() || key.chars().count() > 79 {
                return bad("keys must have 1 to 79 characters");
            }
            if key.chars().any(|c| c as u32 > 0xFF || c == '\0') {
                return bad("keys must be Latin-1 text without NUL");
            }
            if key.starts_with(' ') || key.ends_with(' ') {
                return bad("keys must not start or end with a space");
            }
            if value.contains('\0') {
                return bad("values must not contain NUL");
            }
        }
        Ok(())
    }
}

/// True when every character of `s` is Latin-1 (ISO 8859-1), so PNG `tEXt` can hold it.
pub(crate) fn is_latin1(s: &str) -> bool {
    s.chars().all(|c| (c as u32) <= 0xFF)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_replaces_and_keeps_order() {
        let mut m = Metadata::default();
        m.set("a", "1");
        m.set("b", "2");
        m.set("a", "3");
        assert_eq!(m.entries, vec![("a".into(), "3".into()), ("b".into(), "2".into())]);
        assert_eq!(m.get("b"), Some("2"));
        assert_eq!(m.get("c"), None);
        let merged = m.merged(&[("b".into(), "4".into()), ("c".into(), "5".into())]);
        assert_eq!(merged.get("b"), Some("4"));
        assert_eq!(merged.get("c"), Some("5"));
        assert_eq!(m.get("b"), Some("2"));
    }

    #[test]
    fn validation_rejects_keys_no_format_can_hold() {
        let check = |k: &str, v: &str| Metadata { entries: vec![(k.into(), v.into())] }.validate();
        assert!(check("penumbra.seed", "42").is_ok());
        assert!(check("Comment", "Grüße, 世界").is_ok());
        assert!(check("", "x").is_err());
        assert!(check(&"k".repeat(80), "x").is_err());
        assert!(check("世界", "x").is_err());
        assert!(check(" key", "x").is_err());
        assert!(check("key", "a\0b").is_err());
        assert!(is_latin1("café") && !is_latin1("世界"));
    }
}
