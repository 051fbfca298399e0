//! End-to-end tests of ecles-rs live in `tests/tests/`; this library only carries the README's
//! Rust example, compiled and run as a doctest.

#[doc = include_str!("../../README.md")]
pub struct ReadmeExample;
