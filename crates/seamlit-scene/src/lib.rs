//! seamlit-scene (being written).
