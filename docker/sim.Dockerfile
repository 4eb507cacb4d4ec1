# The vehicle simulator: UMAA SEM Service Providers for GPS and INS.
FROM python:3.11-slim-bookworm
WORKDIR /app
COPY idl/ idl/
COPY backend/ backend/
# the UMAA types are generated from idl/ (never committed; sem_console.idlgen) before the backend is installed
RUN pip install --no-cache-dir "$(grep -o 'cyclonedds==[0-9.]*' backend/pyproject.toml)" \
 && PYTHONPATH=backend python -m sem_console.idlgen \
 && pip install --no-cache-dir ./backend
HEALTHCHECK --interval=5s --timeout=2s --start-period=10s \
  CMD python -c "import os, sys, time; sys.exit(time.time() - os.path.getmtime('/tmp/sem-sim.alive') > 5)"
ENTRYPOINT ["sem-sim", "--health-file", "/tmp/sem-sim.alive", "--state-file", "/data/sim-state.json"]
