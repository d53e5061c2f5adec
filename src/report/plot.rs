//! Placeholder: plots.
