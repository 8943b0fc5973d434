"""The ``ringlab`` command: ``ringlab serve`` (the lab for a class) and ``ringlab loadtest`` (how many students
a server carries)."""
