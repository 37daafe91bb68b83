from diffbot.cli import run

run()
