"""Studies built on runs: convergence orders and error against time (:mod:`.convergence`),
several schemes on one scene (:mod:`.comparison`), the paper's figures (:mod:`.reproduce`)."""
