//! The two flavours of PNML a plan file may be written in.

use std::fmt;
use std::str::FromStr;

use super::error::UnknownDialect;

/// Which PNML flavour to write (reading detects it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Dialect {
    /// As the JARP editor of the Petri Net Plans library writes it: nodes directly
    /// in `net`, values in `<value>`, the plan name in a `PLAN NAME:` comment.
    Jarp,
    /// ISO/IEC 15909-2 place/transition PNML (2009 grammar): nodes in a `page`,
    /// values in `<text>`, the plan name in `net/name`.
    Standard,
}

impl Dialect {
    /// The dialect's name as [`FromStr`] reads it: `jarp` or `standard`.
    pub(crate) const fn as_str(self) -> &'static str {
        match self {
            Dialect::Jarp => "jarp",
            Dialect::Standard => "standard",
        }
    }
}

impl fmt::Display for Dialect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl FromStr for Dialect {
    type Err = UnknownDialect;

    /// `jarp` or `standard`, in any letter case.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        [Dialect::Jarp, Dialect::Standard]
            .into_iter()
            .find(|d| d.as_str().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| UnknownDialect(s.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for d in [Dialect::Jarp, Dialect::Standard] {
            assert_eq!(d.to_string().parse::<Dialect>(), Ok(d));
        }
        assert_eq!("JARP".parse::<Dialect>(), Ok(Dialect::Jarp));
        let err = "iso".parse::<Dialect>().unwrap_err();
        assert!(err.to_string().contains("'iso'"), "{err}");
    }
}
