"""Writers of winder's output files, one module per format; every write is atomic."""
