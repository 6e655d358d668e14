//! Equivalent conicity, EN 15302 (placeholder; being written).
