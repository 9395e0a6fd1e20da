//! End-to-end tests across Morphogen's crates live in `tests/`.
