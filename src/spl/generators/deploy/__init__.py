"""The cloud-side deployment files of the data-acquisition services."""
