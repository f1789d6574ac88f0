"""truckmpc: look-ahead cruise control for heavy trucks, compared against a PI baseline."""
