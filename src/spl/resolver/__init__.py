"""Feature-model analysis (SAT), selection checking and the Resolution Engine (M2M)."""
