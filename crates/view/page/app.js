// Placeholder: the page's client of the Foxglove WebSocket protocol (owned by the page's author).
