// placeholder; delete when adding tests
