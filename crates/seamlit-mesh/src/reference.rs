//! The paper's algorithm.
