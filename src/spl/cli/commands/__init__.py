"""One module per ``spl`` sub-command, each exposing ``command`` (a click command)."""
