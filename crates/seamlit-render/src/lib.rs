//! seamlit-render (being written).
