//! File input and output (behind the `io` feature, on by default): the
//! HDF5 table and results files ([`schema`]), the profile files
//! ([`profile_import`]), one atomic writer for every output file of the
//! workspace ([`atomic`]), the checks of every command's outputs before its
//! work ([`outputs`]) and one reader of numeric text tables ([`csv`]).

pub mod atomic;
pub mod csv;
pub mod lock;
pub mod outputs;
pub mod profile_import;
pub mod schema;

pub use lock::{LockError, OutputLock};
pub use outputs::{Output, OutputError, OutputKind, check_outputs};

pub use atomic::{
    AtomicFile, AtomicWriteError, remove_stale_temporaries, remove_temporaries_in_flight,
    write_atomically, write_atomically_keeping_extension,
};
