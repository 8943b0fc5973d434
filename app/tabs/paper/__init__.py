"""The "Paper results" tab: its view, figures and the replay of the shipped long runs."""
