"""The teacher's dashboard (``/teacher?key=...`` of ``ringlab serve``): the class's progress and answers,
and commands for every student page.  A shell-level package beside the tabs: it reads the lessons and the
server's roster (:mod:`ringlab.live.roster`), and no student page imports or links it."""
