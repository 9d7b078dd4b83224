//! Welding: map every position of every object to a shared id.
