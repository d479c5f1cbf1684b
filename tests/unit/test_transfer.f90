!> The scatter passes: chunked P2G conserves mass and momentum, and the grid work is limited to
!> the box of nodes the material touches without leaving stale values behind.
!>
!> A 2D block (several scatter chunks) falls freely through a tall and wide grid. Before every
!> step a P2G pass alone (on copies of the grid and the stencils: a one-pass step holds the
!> next step's P2G in its grid) gives nodal mass and momentum equal to the particle mass and
!> momentum (to round-off); after every step every node outside the box of the step's nodal
!> loops holds zero mass and velocity, and the box is less than half the grid once the block
!> has left its first layers (the block is narrow, so this also needs the box to be cut along
!> x). The same for a 3D block (USL, linear shape functions).
!>
!> One pass per step (solver.one_pass) gives the answer of separate passes to round-off: the
!> same block, USL and MUSL, with the P2G scattered by the last particle pass of the step.
program test_transfer
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, finish
    use mpm_error, only: error_type
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step
    use mpm_grid, only: grid_type
    use mpm_stencil, only: stencils_type, compute_stencils
    use mpm_transfer, only: p2g, p2g_options_type
    implicit none

    type(test_suite_type) :: suite

    call new_suite(suite, "transfer")
    call falling("2D", '{"name": "fall2", "domain": {"nx": 100, "ny": 200, "dx": 0.01}, '// &
        '"particles": {"ppc": 2}, "materials": [{"name": "m", "type": "linear_elastic", '// &
        '"E": 1e4, "nu": 0.3, "rho": 1000}], "bodies": [{"material": "m", '// &
        '"min": [0.05, 1.5], "max": [0.35, 1.9]}], "gravity": [0, -9.81], '// &
        '"solver": {"scheme": "MUSL", "shape_function": "cpgimp"}, '// &
        '"time": {"tend": 1.0, "dt": 1e-3}}', 300)
    call falling("3D", '{"name": "fall3", "dimension": 3, "domain": {"nx": 30, "ny": 30, '// &
        '"nz": 60, "dx": 0.02}, "particles": {"ppc": 2}, "materials": [{"name": "m", '// &
        '"type": "linear_elastic", "E": 1e4, "nu": 0.3, "rho": 1000}], "bodies": '// &
        '[{"material": "m", "min": [0.04, 0.04, 0.8], "max": [0.16, 0.16, 1.1]}], '// &
        '"gravity": [0, 0, -9.81], "solver": {"scheme": "USL", "shape_function": "linear"}, '// &
        '"time": {"tend": 1.0, "dt": 1e-3}}', 300)
    call one_pass("MUSL APIC", '"scheme": "MUSL", "shape_function": "cpgimp", '// &
        '"transfer": "apic"')
    call one_pass("USL FLIP", '"scheme": "USL", "shape_function": "linear"')
    call finish(suite)

contains

    subroutine falling(label, json, steps)
        character(len=*), intent(in) :: label, json
        integer, intent(in) :: steps

        type(case_type) :: case
        type(simulation_type) :: sim
        type(grid_type) :: grid
        type(stencils_type) :: stc
        type(error_type), allocatable :: error
        integer :: k, dim, p, id, box_nodes
        real(wp) :: mass, pmom(3), gmom(3), worst_mass, worst_mom, bottom
        logical :: stale, partial_loops, narrow

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
        narrow = .true.
        do k = 1, steps
            ! P2G alone (as the step does it): the nodal sums of mass and momentum
            pmom = 0.0_wp
            do p = 1, sim%particles%n
                pmom(1:dim) = pmom(1:dim) + sim%particles%mass(p)*sim%particles%v(:, p)
            end do
            ! on copies: a one-pass step holds the P2G of the next step in its grid
            grid = sim%grid
            stc = sim%stencils
            call compute_stencils(stc, grid, sim%particles, sim%shape, error)
            if (allocated(error)) exit
            call p2g(grid, sim%particles, stc, p2g_options_type(mass=.true., fint=.true.))
            associate (g => grid)
                worst_mass = max(worst_mass, abs(sum(g%mass) - mass)/mass)
                gmom = 0.0_wp
                gmom(1:dim) = sum(g%momentum, dim=2)
                worst_mom = max(worst_mom, norm2(gmom - pmom)/max(norm2(pmom), tiny(1.0_wp)))
            end associate
            call advance(sim, stable_time_step(sim), error)
            if (allocated(error)) exit
            associate (g => sim%grid)
                box_nodes = 0
                do id = 1, g%nnodes
                    if (in_box(g%nn, dim, id, g%active_lo, g%active_hi)) then
                        box_nodes = box_nodes + 1
                    else
                        stale = stale .or. g%mass(id) /= 0 .or. any(g%velocity(:, id) /= 0)
                    end if
                end do
                partial_loops = partial_loops .or. box_nodes < g%nnodes/2
                ! the block spans less than half the width: so does the box (axes but the
                ! slowest)
                narrow = narrow .and. all(g%active_hi(1:dim - 1) - g%active_lo(1:dim - 1) + 1 &
                    < g%nn(1:dim - 1)/2)
            end associate
        end do
        call check(suite, .not. allocated(error), label//": runs")
        call check(suite, sim%stencils%nchunks >= 2, label//": several scatter chunks")
        call check(suite, worst_mass < 1.0e-12_wp, label//": nodal mass = particle mass")
        call check(suite, worst_mom < 1.0e-12_wp, label//": nodal momentum = particle momentum")
        call check(suite, .not. stale, label//": no mass or velocity left outside the loops")
        call check(suite, partial_loops, label//": the nodal loops skip the empty grid")
        call check(suite, narrow, label//": the box is cut across the slowest axis too")
        call check(suite, minval(sim%particles%x(dim, :)) < bottom - 0.3_wp, &
            label//": the block fell through the layers")
    end subroutine falling

    !> A granular column collapsing on a frictional floor (Mohr-Coulomb, particles crossing
    !> cells, leaving chunks, light nodes), in one pass per step and in separate passes: the
    !> same positions and stresses to round-off.
    subroutine one_pass(label, solver)
        character(len=*), intent(in) :: label, solver

        character(len=*), parameter :: head = '{"name": "column", "domain": {"nx": 40, '// &
            '"ny": 12, "dx": 0.01, "boundaries": {"xmin": "sliding", "ymin": {"type": '// &
            '"frictional", "mu": 0.36}}}, "particles": {"ppc": 2}, "materials": [{"name": '// &
            '"g", "type": "mohr_coulomb", "E": 0.84e6, "nu": 0.3, "rho": 2650, "phi": 19.8, '// &
            '"c": 0, "psi": 0}], "bodies": [{"material": "g", "min": [0, 0], "max": [0.1, '// &
            '0.08]}], "gravity": [0, -9.81], "time": {"tend": 1.0, "cfl": 0.5}, "solver": {'
        type(simulation_type) :: sim(2)
        type(case_type) :: case
        type(error_type), allocatable :: error
        integer :: i, k
        real(wp) :: dx_moved, ds
        real(wp), allocatable :: x0(:, :)

        do i = 1, 2
            call read_case_string(head//solver//', "one_pass": '// &
                trim(merge('true ', 'false', i == 1))//'}}', case, error, label)
            if (.not. allocated(error)) call new_simulation(sim(i), case, error)
            call check(suite, .not. allocated(error), label//": set-up")
            if (allocated(error)) return
            x0 = sim(i)%particles%x
            do k = 1, 400
                call advance(sim(i), stable_time_step(sim(i)), error)
                if (allocated(error)) exit
            end do
            call check(suite, .not. allocated(error), label//": runs")
            if (allocated(error)) return
        end do
        call check(suite, sim(1)%one_pass .and. sim(1)%scatter_ready .and. &
            .not. sim(2)%one_pass, label//": one pass in the first run only")
        dx_moved = maxval(abs(sim(1)%particles%x - sim(2)%particles%x))
        ds = maxval(abs(sim(1)%particles%stress - sim(2)%particles%stress))/ &
            maxval(abs(sim(2)%particles%stress))
        print '(a, es9.2, a, es9.2)', "  "//label//": positions differ by", dx_moved, &
            " m, stresses by", ds
        call check(suite, maxval(abs(sim(1)%particles%x - x0)) > 0.01_wp, &
            label//": the column collapses (moves > 1 cm)")
        call check(suite, dx_moved < 1.0e-9_wp .and. ds < 1.0e-7_wp, &
            label//": the same positions and stresses to round-off")
    end subroutine one_pass

    !> Whether node id (1-based) lies in the box lo .. hi (0-based node indices per axis).
    pure logical function in_box(nn, dim, id, lo, hi)
        integer, intent(in) :: nn(3), dim, id, lo(3), hi(3)
        integer :: c(3), r

        r = id - 1
        c(1) = mod(r, nn(1))
        r = r/nn(1)
        c(2) = mod(r, nn(2))
        c(3) = r/nn(2)
        in_box = all(c(1:dim) >= lo(1:dim) .and. c(1:dim) <= hi(1:dim))
    end function in_box

end program test_transfer
