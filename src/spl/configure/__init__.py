"""``spl configure``: a web configurator over a product line or a feature model
(docs/configure.md). :mod:`.workspace` loads what every browser session shares,
:mod:`.session` holds one session's decisions, :mod:`.app` serves both as a page and a
JSON API, :mod:`.drawing` draws the resolved architecture as SVG."""
