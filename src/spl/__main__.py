from spl.cli import main

main()
