//! One module per subcommand.

pub mod compare;
pub mod demo;
pub mod fix;
pub mod inspect;
pub mod render;
