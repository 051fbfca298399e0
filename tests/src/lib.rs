//! End-to-end tests of ecles-rs live in `tests/`; this crate has no library code.
