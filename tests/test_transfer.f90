!> The scatter passes: chunked P2G conserves mass and momentum, and the grid work is limited to
!> the node layers the material touches without leaving stale values behind.
!>
!> A 2D block (several scatter chunks) falls freely through a tall grid. Before every step a
!> P2G pass alone gives nodal mass and momentum equal to the particle mass and momentum (to
!> round-off); after every step every node outside the layers of the step's nodal loops holds
!> zero mass and velocity, and the loops do not cover the whole grid once the block has left
!> its first layers. The same for a 3D block (USL, linear shape functions).
program test_transfer
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, finish
    use mpm_error, only: error_type
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step
    use mpm_stencil, only: compute_stencils
    use mpm_transfer, only: p2g
    implicit none

    type(test_suite_type) :: suite

    call new_suite(suite, "transfer")
    call falling("2D", '{"name": "fall2", "domain": {"nx": 40, "ny": 200, "dx": 0.01}, '// &
        '"particles": {"ppc": 2}, "materials": [{"name": "m", "type": "linear_elastic", '// &
        '"E": 1e4, "nu": 0.3, "rho": 1000}], "bodies": [{"material": "m", '// &
        '"min": [0.05, 1.5], "max": [0.35, 1.9]}], "gravity": [0, -9.81], '// &
        '"solver": {"scheme": "MUSL", "shape_function": "cpgimp"}, '// &
        '"time": {"tend": 1.0, "dt": 1e-3}}', 300)
    call falling("3D", '{"name": "fall3", "dimension": 3, "domain": {"nx": 10, "ny": 10, '// &
        '"nz": 60, "dx": 0.02}, "particles": {"ppc": 2}, "materials": [{"name": "m", '// &
        '"type": "linear_elastic", "E": 1e4, "nu": 0.3, "rho": 1000}], "bodies": '// &
        '[{"material": "m", "min": [0.04, 0.04, 0.8], "max": [0.16, 0.16, 1.1]}], '// &
        '"gravity": [0, 0, -9.81], "solver": {"scheme": "USL", "shape_function": "linear"}, '// &
        '"time": {"tend": 1.0, "dt": 1e-3}}', 300)
    call finish(suite)

contains

    subroutine falling(label, json, steps)
        character(len=*), intent(in) :: label, json
        integer, intent(in) :: steps

        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        integer :: k, dim, p
        real(wp) :: mass, pmom(3), gmom(3), worst_mass, worst_mom, bottom
        logical :: stale, partial_loops

        call read_case_string(json, case, error, label)
        if (allocated(error)) then
            call check(suite, .false., label//": case: "//error%message)
            return
        end if
        call new_simulation(sim, case, error)
        call check(suite, .not. allocated(error), label//": set-up")
        if (allocated(error)) return
        dim = case%dim
        mass = sum(sim%particles%mass)
        bottom = minval(sim%particles%x(dim, :))
        worst_mass = 0.0_wp
        worst_mom = 0.0_wp
        stale = .false.
        partial_loops = .false.
        do k = 1, steps
            ! P2G alone (as the step does it): the nodal sums of mass and momentum
            pmom = 0.0_wp
            do p = 1, sim%particles%n
                pmom(1:dim) = pmom(1:dim) + sim%particles%mass(p)*sim%particles%v(:, p)
            end do
            call compute_stencils(sim%stencils, sim%grid, sim%particles, sim%shape, error)
            if (allocated(error)) exit
            call p2g(sim%grid, sim%particles, sim%stencils, .true., .true., .false.)
            associate (g => sim%grid)
                worst_mass = max(worst_mass, abs(sum(g%mass) - mass)/mass)
                gmom = 0.0_wp
                gmom(1:dim) = sum(g%momentum, dim=2)
                worst_mom = max(worst_mom, norm2(gmom - pmom)/max(norm2(pmom), tiny(1.0_wp)))
            end associate
            call advance(sim, stable_time_step(sim), error)
            if (allocated(error)) exit
            associate (g => sim%grid)
                if (g%first_node > 1) stale = stale .or. any(g%mass(1:g%first_node - 1) /= 0) &
                    .or. any(g%velocity(:, 1:g%first_node - 1) /= 0)
                if (g%last_node < g%nnodes) stale = stale &
                    .or. any(g%mass(g%last_node + 1:) /= 0) &
                    .or. any(g%velocity(:, g%last_node + 1:) /= 0)
                partial_loops = partial_loops .or. &
                    (g%last_node - g%first_node + 1 < g%nnodes/2)
            end associate
        end do
        call check(suite, .not. allocated(error), label//": runs")
        call check(suite, sim%stencils%nchunks >= 2, label//": several scatter chunks")
        call check(suite, worst_mass < 1.0e-12_wp, label//": nodal mass = particle mass")
        call check(suite, worst_mom < 1.0e-12_wp, label//": nodal momentum = particle momentum")
        call check(suite, .not. stale, label//": no mass or velocity left outside the loops")
        call check(suite, partial_loops, label//": the nodal loops skip the empty grid")
        call check(suite, minval(sim%particles%x(dim, :)) < bottom - 0.3_wp, &
            label//": the block fell through the layers")
    end subroutine falling

end program test_transfer
