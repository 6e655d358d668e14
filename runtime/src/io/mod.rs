//! File input and output shared by the workspace's crates (behind the `io`
//! feature): one atomic writer for every output file ([`atomic`]), one
//! reader of numeric text tables ([`csv`]).

pub mod atomic;
pub mod csv;

pub use atomic::{
    AtomicFile, AtomicWriteError, write_atomically, write_atomically_keeping_extension,
};
