//! A game log as one self-contained HTML page: the field, the players with
//! their numbers, the ball, the cycle and the episode time, play and pause, a
//! slider and a speed control, and each plan-driven keeper's current action
//! and last choice with the values of its options. The page loads nothing
//! (no network, no external script): the log is embedded as JSON and drawn on
//! a canvas by a script in the page.
//!
//! For tests and scripts, the page keeps what it drew in the data attributes
//! of `#drawn`: `cycle`, `canvas` (the canvas's page position), `transform`
//! (pixels per metre and the pixel position of the origin) and `objects`
//! (`b:x,y;l1:x,y;...`, canvas pixels). Opening it with `#cycle=N` shows cycle N.

use super::rcg::GameLog;

/// The page, with `__TITLE__` and `__LOG__` to fill in.
const TEMPLATE: &str = include_str!("replay.html");

/// Escapes text for HTML element content.
fn html_escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
    out
}

/// The page replaying `log`, titled `title`.
pub fn replay_page(log: &GameLog, title: &str) -> Result<String, serde_json::Error> {
    // Inside a script element, "</" could close it: JSON allows "<\/" instead.
    let data = serde_json::to_string(log)?.replace("</", "<\\/");
    Ok(TEMPLATE
        .replace("__TITLE__", &html_escape(title))
        .replace("__LOG__", &data))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_page_embeds_the_log_and_loads_nothing() {
        let text = "ULG5\n(server_param (keepaway 1)(keepaway_length 20)(keepaway_width 20))\n\
                    (msg 0 1 \"</script><b>\")\n\
                    (show 0 ((b) -6 -6 0 0) ((l 1) 0 0x1 9 -7 0 0 57 0 (v h 90) (s 8000 1 1 130600) (c 0 0 0 0 0 0 0 0 0 0 0)))\n";
        let log = GameLog::parse(text).expect("a log");
        let page = replay_page(&log, "a <title>").expect("a page");
        assert!(page.contains("<title>a &lt;title&gt;</title>"));
        assert!(!page.contains("</script><b>"));
        assert!(page.contains("\"keepaway\":[20.0,20.0]"));
        for remote in ["http://", "https://", "src=", "<link", "import "] {
            assert!(!page.contains(remote), "the page loads something: {remote}");
        }
    }
}
