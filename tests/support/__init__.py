"""What the tests of every layer share: models, generators of random lines, runners of
real services and processes."""
