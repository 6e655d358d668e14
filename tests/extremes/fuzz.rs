//! Fuzzing the input parsers with proptest (issue 7, part A).
