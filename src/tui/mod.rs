pub mod theme;
pub mod tree;
