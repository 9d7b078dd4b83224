//! seamlit-io (being written).
