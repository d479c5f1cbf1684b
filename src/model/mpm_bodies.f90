!> Fill the bodies of a case with particles.
module mpm_bodies
    use mpm_kinds, only: wp, i8
    use mpm_error, only: error_type, fatal_error, exit_other
    use mpm_case, only: case_type, body_subcell_range, dist_random
    use mpm_particles, only: particles_type, new_particles
    implicit none
    private
    public :: count_body_particles, create_particles, body_cell_histogram

contains

    !> Number of particles a body holds (see body_subcell_range for the placement rule).
    pure integer(i8) function count_body_particles(case, b)
        type(case_type), intent(in) :: case
            !! resolved case
        integer, intent(in) :: b
            !! body index

        integer :: lo(3), hi(3), a

        call body_subcell_range(case, case%bodies(b), lo, hi)
        count_body_particles = 1_i8
        do a = 1, case%dim
            count_body_particles = count_body_particles*int(max(0, hi(a) - lo(a) + 1), i8)
        end do
    end function count_body_particles

    !> Create the particles of every body: positions, volumes, masses, velocities, sizes.
    !>
    !> With `slab`, only the particles whose cell along axis slab(1) is in [slab(2), slab(3))
    !> (an image's part of the grid, mpm_decomposition), numbered in particles%id by their
    !> index among all particles.
    subroutine create_particles(case, particles, error, nstate, slab)
        type(case_type), intent(in) :: case
            !! resolved case
        type(particles_type), intent(out) :: particles
            !! the particles, body by body in case order
        type(error_type), allocatable, intent(out) :: error
            !! set when memory cannot be allocated
        integer, intent(in), optional :: nstate
            !! material state variables per particle (default 0)
        integer, intent(in), optional :: slab(3)
            !! axis, first cell, one past the last cell of the particles to keep

        integer :: b, a, p, q, s(3), i, j, k, dim, pass, stat
        integer(i8) :: total
        integer :: lo(3), hi(3)
        real(wp) :: h, vol, x(3)
        character(len=256) :: msg

        dim = case%dim
        total = 0
        do b = 1, size(case%bodies)
            total = total + count_body_particles(case, b)
        end do
        h = case%dx/real(case%ppc, wp)
        vol = h**dim
        if (.not. present(slab)) then
            call new_particles(particles, dim, int(total), error, nstate)
            if (allocated(error)) return
        end if
        ! with a slab: count the particles kept, then create them
        do pass = 1, merge(2, 1, present(slab))
            if (pass == 2) then
                call new_particles(particles, dim, q, error, nstate)
                if (allocated(error)) return
                allocate (particles%id(q), stat=stat, errmsg=msg)
                if (stat /= 0) then
                    call fatal_error(error, "cannot allocate the particle ids: "//trim(msg), &
                        exit_other)
                    return
                end if
            end if
            p = 0
            q = 0
            do b = 1, size(case%bodies)
                associate (body => case%bodies(b), &
                           rho => case%materials(case%bodies(b)%material)%density)
                    call body_subcell_range(case, body, lo, hi)
                    do k = lo(3), hi(3)
                        do j = lo(2), hi(2)
                            do i = lo(1), hi(1)
                                p = p + 1
                                s = [i, j, k]
                                x = particle_position(case, s, p, h)
                                if (present(slab)) then
                                    a = global_cell_of(case, x(slab(1)), slab(1))
                                    if (a < slab(2) .or. a >= slab(3)) cycle
                                end if
                                q = q + 1
                                if (present(slab) .and. pass == 1) cycle
                                if (present(slab)) particles%id(q) = p
                                particles%x(:, q) = x(1:dim)
                                particles%v(:, q) = body%velocity(1:dim)
                                particles%volume(q) = vol
                                particles%volume0(q) = vol
                                particles%mass(q) = rho*vol
                                particles%lp0(:, q) = 0.5_wp*h
                                particles%lp(:, q) = 0.5_wp*h
                                particles%material(q) = body%material
                            end do
                        end do
                    end do
                end associate
            end do
        end do
    end subroutine create_particles

    !> Particles per cell layer along axis a, of all the particles the bodies hold.
    subroutine body_cell_histogram(case, a, histogram)
        type(case_type), intent(in) :: case
            !! resolved case
        integer, intent(in) :: a
            !! axis
        integer(i8), intent(out) :: histogram(0:)
            !! particles per cell layer (0 : ncells(a) - 1)

        integer :: b, p, s(3), i, j, k, lo(3), hi(3), c
        real(wp) :: h, x(3)

        histogram = 0
        h = case%dx/real(case%ppc, wp)
        p = 0
        do b = 1, size(case%bodies)
            call body_subcell_range(case, case%bodies(b), lo, hi)
            do k = lo(3), hi(3)
                do j = lo(2), hi(2)
                    do i = lo(1), hi(1)
                        p = p + 1
                        s = [i, j, k]
                        x = particle_position(case, s, p, h)
                        c = global_cell_of(case, x(a), a)
                        histogram(c) = histogram(c) + 1
                    end do
                end do
            end do
        end do
    end subroutine body_cell_histogram

    !> Position of particle p (index among all particles) in sub-cell s of spacing h.
    pure function particle_position(case, s, p, h) result(x)
        type(case_type), intent(in) :: case
        integer, intent(in) :: s(3), p
        real(wp), intent(in) :: h
        real(wp) :: x(3)

        integer :: a
        real(wp) :: jitter(3)

        jitter = 0.5_wp
        if (case%distribution == dist_random) then
            do a = 1, case%dim
                jitter(a) = uniform01(case%seed, p, a)
            end do
        end if
        x = 0.0_wp
        do a = 1, case%dim
            x(a) = case%origin(a) + (real(s(a), wp) + jitter(a))*h
        end do
    end function particle_position

    !> Cell (0-based, along axis a) of a coordinate in the whole grid, clamped to the grid
    !> (as mpm_decomposition's global_cell).
    pure integer function global_cell_of(case, x, a)
        type(case_type), intent(in) :: case
        real(wp), intent(in) :: x
        integer, intent(in) :: a
        global_cell_of = min(max(int((x - case%origin(a))/case%dx), 0), case%ncells(a) - 1)
    end function global_cell_of

    !> Reproducible uniform number in (0.05, 0.95) from (seed, particle, axis): splitmix64 hash.
    !>
    !> Independent of loop order and thread count; the margin keeps a particle off the
    !> faces of its sub-cell.
    pure real(wp) function uniform01(seed, p, axis)
        integer, intent(in) :: seed
            !! user seed
        integer, intent(in) :: p
            !! particle index
        integer, intent(in) :: axis
            !! coordinate axis

        integer(i8) :: z

        z = int(seed, i8)*1000003_i8 + int(p, i8)*3_i8 + int(axis, i8)
        z = z + (-7046029254386353131_i8)
        z = ieor(z, shiftr(z, 30))*(-4658895280553007687_i8)
        z = ieor(z, shiftr(z, 27))*(-7723592293110705685_i8)
        z = ieor(z, shiftr(z, 31))
        uniform01 = 0.05_wp + 0.9_wp*real(shiftr(z, 11), wp)/real(shiftl(1_i8, 53), wp)
    end function uniform01

end module mpm_bodies
