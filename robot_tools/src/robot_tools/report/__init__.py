"""A recorded match: its bag read, its figures measured, its report drawn; a replay's verdict."""
