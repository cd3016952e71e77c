"""Layer 4: the comparison report (Markdown and HTML) built from suite result rows."""
