"""The trajectory explorer: a viser app generated from the mission contract (`solvers`).

    python -m explorer [--host 127.0.0.1] [--port 8080] [--mission KEY] [--shared]
                       [--time-limit S]                                   # serve the app
    python -m explorer.capture --mission lunar-landing --out shot.png     # headless PNG
    python -m explorer.capture --all --out DIR                            # every mission
    python -m explorer.export --mission KEY [--preset NAME] --out DIR     # offline copy
"""
