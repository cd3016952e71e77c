"""Layer 5: adapters to other ecosystems (navground behaviour plugin, …)."""
