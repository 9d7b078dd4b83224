//! Loading benchmarks (written later).

fn main() {}
