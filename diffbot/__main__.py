from diffbot.cli import main

main(prog_name="diffbot")
