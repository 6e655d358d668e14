//! Bad input everywhere a user types or supplies something (issue 7, part A).
