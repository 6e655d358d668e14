//! Profile file import (placeholder; being written).
