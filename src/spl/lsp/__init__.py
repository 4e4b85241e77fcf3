"""``spl lsp``: a language server for the .tsm, .fm and .rm languages."""
