"""Style and small page helpers shared by every tab (a leaf: imports only ringcore and the web stack)."""
