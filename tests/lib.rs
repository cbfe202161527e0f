//! Integration tests, compiled as one binary.

mod backends;
mod scene;
