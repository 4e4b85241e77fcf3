"""The feature-model formats of the community: UVL and FeatureIDE XML, read and written."""
