# bench/sim/scenes.sh — sourced, not run: the three scenes of the relay and
# master-cost points (the 256-worker efficiency swings by several points
# with the scene, so one scene says little).
#
# sim_scenes WORK: WORK/spheres50-s1|2|3.pov, generated where missing
# (csgtrace gen spheres --count 50 --occupancy 0.5 --seed 1|2|3).
sim_scenes() {
    local seed scene
    for seed in 1 2 3; do
        scene=$1/spheres50-s$seed.pov
        [ -f "$scene" ] || "$ROOT/build/csgtrace" gen spheres --count 50 --occupancy 0.5 \
            --seed $seed -o "$scene"
    done
}
