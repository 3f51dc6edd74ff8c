"""Study layer: TOML study file -> validated configuration -> plan of cases -> case runner."""
