!> Results identical bit for bit with 1, 2 and 4 OpenMP threads.
!>
!> The scatters sum chunk buffers in chunk order, the chunks depend on the particle count
!> only, and every energy sum is taken over fixed blocks (mpm_stencil, mpm_transfer,
!> mpm_solver): the thread count must not change a single bit of the state. Three scenes, each
!> with enough particles for several chunks, run the same number of steps with 1, 2 and 4
!> threads: a 2D cpGIMP MUSL granular collapse (Mohr-Coulomb with separation, APIC, frictional
!> floor, F-bar), a 3D cpGIMP USL elastic column with local damping, and a 2D linear USF
!> block with FLIP/PIC blending. Positions, velocities, stresses, material state, volumes and
!> the energy terms are compared exactly, and so are those of a run whose thread count changes
!> from step to step (1, 2, 4, 2, ...), as mpm_threads changes it during a run. (Without
!> OpenMP the runs are only repeated.)
program test_threads
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, finish
    use mpm_error, only: error_type
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step, &
        compute_energies, energy_record
    !$ use omp_lib, only: omp_set_num_threads
    implicit none

    type(test_suite_type) :: suite
    integer, parameter :: changing = 0
        !! run(): 1, 2, 4, 2, 1, 2, ... threads, one count per step

    call new_suite(suite, "threads")
    call compare("2D collapse, cpGIMP MUSL APIC F-bar, Mohr-Coulomb", &
        '{"name": "collapse", "domain": {"nx": 60, "ny": 24, "dx": 0.01, '// &
        '"boundaries": {"xmin": "sliding", "xmax": "sliding", '// &
        '"ymin": {"type": "frictional", "mu": 0.4}}}, "particles": {"ppc": 3}, '// &
        '"materials": [{"name": "sand", "type": "mohr_coulomb", "E": 1e6, "nu": 0.3, '// &
        '"rho": 2000, "phi": 30, "c": 0, "psi": 0, "separation": true}], '// &
        '"bodies": [{"material": "sand", "min": [0, 0], "max": [0.3, 0.2]}], '// &
        '"gravity": [0, -9.81], "solver": {"scheme": "MUSL", "shape_function": "cpgimp", '// &
        '"transfer": "apic", "locking_correction": "fbar"}, '// &
        '"time": {"tend": 1.0, "cfl": 0.5}}', 50)
    call compare("3D column, cpGIMP USL, elastic, local damping", &
        '{"name": "column", "dimension": 3, "domain": {"nx": 16, "ny": 16, "nz": 48, '// &
        '"dx": 0.025, "boundaries": {"zmin": "fixed"}}, "particles": {"ppc": 2}, '// &
        '"materials": [{"name": "rock", "type": "linear_elastic", "E": 1e6, "nu": 0.25, '// &
        '"rho": 2000}], "bodies": [{"material": "rock", "min": [0.1, 0.1, 0], '// &
        '"max": [0.3, 0.3, 1.0]}], "gravity": [0, 0, -9.81], '// &
        '"damping": {"type": "local", "value": 0.05}, '// &
        '"solver": {"scheme": "USL", "shape_function": "cpgimp"}, '// &
        '"time": {"tend": 1.0, "cfl": 0.5}}', 20)
    call compare("2D block, linear USF, FLIP 0.95", &
        '{"name": "block", "domain": {"nx": 80, "ny": 80, "dx": 0.0125, '// &
        '"boundaries": {"ymin": "fixed"}}, "particles": {"ppc": 2}, '// &
        '"materials": [{"name": "m", "type": "linear_elastic", "E": 1e5, "nu": 0.3, '// &
        '"rho": 1000}], "bodies": [{"material": "m", "min": [0.25, 0], "max": [0.75, 0.8], '// &
        '"velocity": [0.3, 0]}], "gravity": [0, -9.81], '// &
        '"solver": {"scheme": "USF", "shape_function": "linear", "flip_fraction": 0.95}, '// &
        '"time": {"tend": 1.0, "cfl": 0.5}}', 30)
    call finish(suite)

contains

    !> Run `steps` steps of the case with 1, 2 and 4 threads and compare the states exactly.
    subroutine compare(label, json, steps)
        character(len=*), intent(in) :: label, json
        integer, intent(in) :: steps

        type(simulation_type) :: one, many
        integer :: threads(2), t
        logical :: ok
        character(len=16) :: buf

        call run(json, steps, 1, one, ok)
        call check(suite, ok, label//": runs on 1 thread")
        if (.not. ok) return
        call check(suite, one%stencils%nchunks >= 2, label//": several scatter chunks")
        threads = [2, 4]
        do t = 1, size(threads)
            write (buf, "(i0)") threads(t)
            call run(json, steps, threads(t), many, ok)
            call check(suite, ok, label//": runs on "//trim(buf)//" threads")
            if (.not. ok) cycle
            call check(suite, same(one, many), label//": "//trim(buf)//" threads give the "// &
                "bits of 1 thread")
        end do
        call run(json, steps, changing, many, ok)
        call check(suite, ok, label//": runs with a thread count changing every step")
        if (ok) call check(suite, same(one, many), label//": a thread count changing every "// &
            "step gives the bits of 1 thread")
        !$ call omp_set_num_threads(1)
    end subroutine compare

    subroutine run(json, steps, threads, sim, ok)
        character(len=*), intent(in) :: json
        integer, intent(in) :: steps, threads
            !! thread count, or `changing`
        type(simulation_type), intent(out) :: sim
        logical, intent(out) :: ok

        type(case_type) :: case
        type(error_type), allocatable :: error
        integer :: k
        integer, parameter :: cycle_of_counts(4) = [1, 2, 4, 2]

        ok = .false.
        !$ call omp_set_num_threads(max(1, threads))
        if (threads < 0) return   ! (threads is only used with OpenMP)
        call read_case_string(json, case, error, "threads")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call new_simulation(sim, case, error)
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        do k = 1, steps
            !$ if (threads == changing) &
            !$     call omp_set_num_threads(cycle_of_counts(mod(k - 1, 4) + 1))
            call advance(sim, stable_time_step(sim), error)
            if (allocated(error)) then
                print "(a)", error%message
                return
            end if
        end do
        call compute_energies(sim)
        ok = .true.
    end subroutine run

    !> Whether two states are identical bit for bit (and moved at all).
    logical function same(a, b)
        type(simulation_type), intent(in) :: a, b

        same = all(a%particles%x == b%particles%x) .and. all(a%particles%v == b%particles%v) &
            .and. all(a%particles%stress == b%particles%stress) &
            .and. all(a%particles%state == b%particles%state) &
            .and. all(a%particles%volume == b%particles%volume) &
            .and. all(energy_record(a%energy) == energy_record(b%energy)) .and. a%time == b%time
        if (allocated(a%particles%affine)) same = same .and. &
            all(a%particles%affine == b%particles%affine)
        same = same .and. any(a%particles%u /= 0.0_wp)
    end function same

end program test_threads
