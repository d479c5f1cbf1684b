!> The memory check of a run: an estimate of what a case needs on this image, made before
!> anything is allocated, against what the machine (or the job's limit) has available.
module mpm_memory_check
    use mpm_kinds, only: wp, i8
    use mpm_error, only: error_type, fatal_error, exit_input
    use mpm_system, only: available_memory_bytes
    use mpm_strings, only: int_text, text_or
    use mpm_particles, only: created_particle_bytes
    use mpm_case, only: case_type
    use mpm_case_materials, only: state_variable_count
    use mpm_case_guard, only: snapshot_in_memory
    use mpm_solver, only: has_text
    use mpm_parallel, only: image_id, image_count
    use mpm_state, only: state_particle_count
    use mpm_shape, only: shape_type
    use mpm_shape_factory, only: new_shape
    use mpm_bodies, only: count_body_particles
    implicit none
    private
    public :: memory_estimate, check_memory

contains
    !> Memory a case needs on this image [bytes], estimated before anything is allocated:
    !> particles (with the displacement and strain they hold while being created, the
    !> stencils and order of a step, the guard's copy) and grid nodes (fields and scatter
    !> buffers). `particles` is the number of particles of the whole case.
    function memory_estimate(case, particles, nodes_per_axis) result(bytes)
        type(case_type), intent(in) :: case
            !! resolved case
        integer(i8), intent(in) :: particles
            !! particles of the case
        integer, intent(in) :: nodes_per_axis
            !! support width of the case's shape function (shape_type%nodes_per_axis)
        real(wp) :: bytes
            !! estimate [bytes]

        real(wp), parameter :: real_bytes = storage_size(1.0_wp)/8, int_bytes = 4
        real(wp) :: per_particle, per_node, d, nps, nodes

        d = real(case%dim, wp)
        nps = real(nodes_per_axis, wp)
        ! the arrays of the field table that new_particles allocates, with the state
        ! variables of the materials, the APIC affine velocities and the ids of several images
        per_particle = real(created_particle_bytes(case%dim, state_variable_count(case%materials), &
            case%solver%apic, image_count() > 1), wp)
        if (case%guard%snapshot_steps > 0 .and. case%guard%snapshot_in == snapshot_in_memory) then
            per_particle = 2.0_wp*per_particle
        end if
        ! stencils: weights and gradients, first node, order, cell
        per_particle = per_particle + real_bytes*(2.0_wp*nps - 1.0_wp)*d + int_bytes*(d + 2.0_wp)
        ! nodal fields (mass, momentum, forces, velocity, acceleration; constraints) and the
        ! scatter buffers (mass, momentum, force per node at least)
        per_node = real_bytes*(1.0_wp + 5.0_wp*d) + 4.0_wp*d + real_bytes*(2.0_wp*d + 1.0_wp)
        nodes = product(real(case%domain%ncells(1:case%dim), wp) + 1.0_wp)
        bytes = (per_particle*real(particles, wp) + per_node*nodes)/real(image_count(), wp)
    end function memory_estimate

    !> Refuse a case whose memory estimate exceeds what this machine (or the job's memory
    !> limit) has available, before allocating it.
    subroutine check_memory(case, error, restart)
        type(case_type), intent(in) :: case
            !! resolved case
        type(error_type), allocatable, intent(out) :: error
            !! set (exit_input) when the case cannot fit
        character(len=*), intent(in), optional :: restart
            !! checkpoint the particles come from

        integer(i8) :: particles, available, n
        integer :: b
        real(wp) :: need
        class(shape_type), allocatable :: shape
        character(len=:), allocatable :: hint

        particles = 0
        if (present(restart)) then
            particles = max(0_i8, state_particle_count(restart))
        else if (has_text(case%load_state)) then
            particles = max(0_i8, state_particle_count(case%load_state))
        else
            ! (the reader counted them; a case made in code is counted here)
            do b = 1, size(case%bodies)
                n = case%bodies(b)%particles
                if (n < 0) n = count_body_particles(case, b)
                if (n > 0) particles = particles + n
            end do
        end if
        call new_shape(shape, trim(case%solver%shape_function), error, &
            text_or(case%file, "?"))
        if (allocated(error)) return
        need = memory_estimate(case, particles, shape%nodes_per_axis())
        available = available_memory_bytes()
        if (available < 0 .or. need <= real(available, wp)) return
        hint = ""
        if (case%guard%snapshot_steps > 0 .and. case%guard%snapshot_in == snapshot_in_memory) then
            hint = "; guard.snapshot_in = ""file"" keeps the guard's copy of the particles on disk"
        end if
        call fatal_error(error, case%file//": the case needs about "//size_text(need)// &
            " of memory"//trim(merge(" per image", "          ", image_count() > 1))//" ("// &
            int_text(particles)//" particles and "// &
            int_text(int(product(real(case%domain%ncells(1:case%dim), wp) + 1.0_wp), i8))// &
            " grid nodes) but "//size_text(real(available, wp))//" is available; use a "// &
            "larger domain.dx, fewer particles.ppc, a smaller domain, or more images "// &
            "(docs/hpc.md)"//hint, exit_input)
        if (image_id() /= 1) error%message = ""
    end subroutine check_memory

    !> "12.3 GB", "512 MB", ...
    function size_text(bytes) result(text)
        real(wp), intent(in) :: bytes
        character(len=:), allocatable :: text

        character(len=32) :: buf

        if (bytes >= 1.0e9_wp) then
            write (buf, "(f0.1,a)") bytes/1.0e9_wp, " GB"
        else
            write (buf, "(f0.1,a)") bytes/1.0e6_wp, " MB"
        end if
        text = trim(buf)
        if (text(1:1) == ".") text = "0"//text
    end function size_text

end module mpm_memory_check
