"""The three textual languages: textX grammars (``*.tx``) next to the builders that
turn a parse tree into a pyecore model, resolve names and report located errors."""
