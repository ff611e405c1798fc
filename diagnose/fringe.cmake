# Fringe image sets against the ideal fringe model (issue 8).
list(APPEND RAMTK_DIAGNOSE_KIND_SOURCES src/fringe_model.cpp src/fringe_candidates.cpp src/fringe_diagnose.cpp
     src/fringe_pictures.cpp src/fringe_hidden.cpp src/fringe_noise.cpp)
