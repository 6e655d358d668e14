//! Error chains as users read them. The library errors carry their cause
//! both in their message (`"…: {source}"`, so that a message read alone is
//! complete) and as their `source()` (so that programs can walk it); printed
//! naively, every cause would appear twice. These helpers drop a cause whose
//! text the message before it already ends with.

/// The messages of `e`'s chain, outermost first, without the repeats.
pub fn chain_messages(e: &anyhow::Error) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if out.last().is_some_and(|prev| prev.ends_with(&text)) {
            continue;
        }
        out.push(text);
    }
    out
}

/// The chain on one line, joined by ": " (the summary's `error`, tables).
pub fn chain_text(e: &anyhow::Error) -> String {
    chain_messages(e).join(": ")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An error in the library style: its cause in the message and as
    /// its source.
    #[derive(Debug)]
    struct Outer {
        source: Inner,
    }

    impl std::fmt::Display for Outer {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            write!(f, "outer at t = 1 s: {}", self.source)
        }
    }

    impl std::error::Error for Outer {
        fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
            Some(&self.source)
        }
    }

    #[derive(Debug)]
    struct Inner;

    impl std::fmt::Display for Inner {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str("inner failed")
        }
    }

    impl std::error::Error for Inner {}

    #[test]
    fn a_cause_already_in_the_message_is_not_repeated() {
        let e = anyhow::Error::new(Outer { source: Inner }).context("running the scene");
        assert_eq!(
            chain_messages(&e),
            vec!["running the scene", "outer at t = 1 s: inner failed"]
        );
        assert_eq!(
            chain_text(&e),
            "running the scene: outer at t = 1 s: inner failed"
        );
        // The naive chain repeats it.
        assert_eq!(format!("{e:#}").matches("inner failed").count(), 2);
    }

    #[test]
    fn distinct_causes_are_all_kept() {
        let e = anyhow::anyhow!("root").context("middle").context("top");
        assert_eq!(chain_messages(&e), vec!["top", "middle", "root"]);
    }
}
