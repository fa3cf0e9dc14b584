// Placeholder: the page's reader of uncompressed MCAP recordings (owned by the page's author).
