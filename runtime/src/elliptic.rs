//! Complete elliptic integrals (placeholder; being written).
