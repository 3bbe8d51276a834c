"""Reading and writing files. Math modules never import from here."""
