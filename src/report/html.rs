//! Placeholder: HTML.
