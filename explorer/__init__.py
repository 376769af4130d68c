"""The trajectory explorer: a viser app generated from the mission contract (`solvers`).

    python -m explorer [--host 127.0.0.1] [--port 8080] [--mission KEY]   # serve the app
    python -m explorer.capture --mission lunar-landing --out shot.png     # headless PNG
"""
