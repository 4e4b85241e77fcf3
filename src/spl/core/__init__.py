"""What every layer of spl uses: located diagnostics, generic operations on pyecore models,
whole-or-nothing file writes, the collector pause and process lifetimes."""
