//! The properties of each script type (`camera`, `entity`, `settings`, `texture`, `vec3`,
//! `path`), so that an unknown or read-only property fails with a message that names the
//! object, suggests the closest property and lists them all, rather than Rhai's "a setter is
//! not registered"; and the message for a name the scene does not have ([`unknown_name`]).

use super::scene::{CAMERA_PROPERTIES, SETTINGS_PROPERTIES};
use super::texture::TEXTURE_PROPERTIES;
use crate::scene::error::shown;

/// The properties and methods of one script type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Properties {
    /// The type as scripts name it (and as it is registered with Rhai).
    pub object: &'static str,
    /// Properties that can be read and written.
    pub writable: &'static [&'static str],
    /// Properties that can only be read.
    pub read_only: &'static [&'static str],
    /// Methods, as called (`focus_on(name)`), mentioned after the properties.
    pub methods: &'static [&'static str],
}

/// Properties of entities (objects and lights; each kind refuses the other's with its own
/// message).
pub const ENTITY_PROPERTIES: &[&str] = &[
    "position",
    "rotation",
    "scale",
    "visible",
    "kd",
    "ks",
    "shininess",
    "kr",
    "kt",
    "ior",
    "glossiness",
    "colour",
    "intensity",
];

/// Every script type with properties.
pub const TYPES: &[Properties] = &[
    Properties {
        object: "camera",
        writable: CAMERA_PROPERTIES,
        read_only: &[],
        methods: &["focus_on(name)"],
    },
    Properties {
        object: "entity",
        writable: ENTITY_PROPERTIES,
        read_only: &["name", "centre"],
        methods: &[],
    },
    Properties { object: "settings", writable: SETTINGS_PROPERTIES, read_only: &[], methods: &[] },
    Properties { object: "texture", writable: TEXTURE_PROPERTIES, read_only: &["name"], methods: &[] },
    Properties { object: "vec3", writable: &["x", "y", "z"], read_only: &[], methods: &[] },
    Properties {
        object: "path",
        writable: &[],
        read_only: &["length", "points"],
        methods: &["at(u)", "tangent(u)"],
    },
];

impl Properties {
    /// The properties of the script type called `object`, if it has any.
    pub fn of(object: &str) -> Option<&'static Properties> {
        TYPES.iter().find(|p| p.object == object)
    }

    /// Every property name, writable first.
    pub fn all(&self) -> impl Iterator<Item = &'static str> {
        self.writable.iter().chain(self.read_only).copied()
    }

    /// Whether `name` is a property at all.
    pub fn has(&self, name: &str) -> bool {
        self.all().any(|p| p == name)
    }

    /// Why `object.name` cannot be read or written: the closest property and the list of them.
    pub fn unknown(&self, name: &str) -> String {
        let object = self.object;
        match closest(name, self.all()) {
            Some(p) => format!("{object} has no property `{name}`; did you mean `{p}`? {}", self.listing()),
            None => format!("{object} has no property `{name}`; {}", self.listing()),
        }
    }

    /// Why `object.name = …` fails for a read-only property.
    pub fn read_only(&self, name: &str) -> String {
        format!("{}.{name} can be read but not written; {}", self.object, self.listing())
    }

    /// `camera has: position, look_at, …, focus_distance (methods: focus_on(name))`.
    fn listing(&self) -> String {
        let mut text = format!("{} has: {}", self.object, self.writable.join(", "));
        if !self.read_only.is_empty() {
            let sep = if self.writable.is_empty() { "" } else { ", " };
            text += &format!("{sep}{} (read only)", self.read_only.join(", "));
        }
        if !self.methods.is_empty() {
            text += &format!("; methods: {}", self.methods.join(", "));
        }
        text
    }
}

/// Why there is no `kind` (`entity`, `texture`) called `name`: the closest name, if one is
/// close enough to be a typo, and the names there are (the first 24, sorted).
pub fn unknown_name<'a>(kind: &str, name: &str, names: impl IntoIterator<Item = &'a str>) -> String {
    const SHOWN: usize = 24;
    let mut names: Vec<&str> = names.into_iter().collect();
    if names.is_empty() {
        return format!("no {kind} named `{}` in the scene; it has no {kind}s", shown(name));
    }
    names.sort_unstable();
    let closest = closest(name, names.iter().copied())
        .map_or(String::new(), |n| format!(" (did you mean `{}`?)", shown(n)));
    let more = match names.len().saturating_sub(SHOWN) {
        0 => String::new(),
        n => format!(" and {n} more"),
    };
    names.truncate(SHOWN);
    let names: Vec<String> = names.into_iter().map(shown).collect();
    format!("no {kind} named `{}` in the scene{closest}; it has: {}{more}", shown(name), names.join(", "))
}

/// The candidate closest to `name` by edit distance, if it is close enough to be a typo (at
/// most 2 edits, or a third of the candidate's length, and not every character of it).
pub fn closest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    candidates
        .into_iter()
        .map(|c| (edit_distance(name, c), c))
        .min()
        .filter(|(d, c)| *d <= 2.max(c.len() / 3) && *d < c.chars().count())
        .map(|(_, c)| c)
}

/// Levenshtein distance between two names.
pub fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let next = (diagonal + usize::from(ca != *cb)).min(row[j] + 1).min(row[j + 1] + 1);
            diagonal = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edit_distance_counts_insertions_deletions_and_substitutions() {
        assert_eq!(edit_distance("ball", "ball"), 0);
        assert_eq!(edit_distance("bal", "ball"), 1);
        assert_eq!(edit_distance("red_bal", "red_ball"), 1);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(edit_distance("", "abc"), 3);
    }

    #[test]
    fn a_typo_suggests_the_closest_property_and_lists_them_all() {
        let camera = Properties::of("camera").unwrap();
        assert_eq!(
            camera.unknown("positon"),
            "camera has no property `positon`; did you mean `position`? camera has: position, look_at, \
             up, fov, aperture, focus_distance; methods: focus_on(name)"
        );
        let entity = Properties::of("entity").unwrap();
        assert_eq!(closest("color", entity.all()), Some("colour"));
        assert_eq!(closest("w", ["x", "y", "z"]), None, "a one-letter name is no typo of another");
        assert!(entity
            .unknown("weight")
            .starts_with("entity has no property `weight`; entity has: position,"));
        assert!(
            entity.read_only("centre").contains("name, centre (read only)"),
            "{}",
            entity.read_only("centre")
        );
        assert_eq!(Properties::of("i64"), None);
    }
}
